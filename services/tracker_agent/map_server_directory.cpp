// Map servers of the vehicle's mosaic: owned tile ranges and reachability.
#include "tracker_agent/map_server_directory.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "transport/mosaic_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::tracker_agent {

Result<std::unique_ptr<MapServerDirectory>> MapServerDirectory::Create(
    const transport::Participant& participant, transport::TileClient* tiles,
    const mosaic::MosaicLayout& layout, std::chrono::duration<double> timeout) {
  auto watch = transport::ServiceWatch::Create(participant, "map_server");
  if (!watch.ok()) return watch.status();
  auto directory = std::unique_ptr<MapServerDirectory>(new MapServerDirectory(
      tiles, std::move(watch).value(), layout,
      std::chrono::duration_cast<transport::ServiceWatch::Clock::duration>(timeout)));
  directory->Poll();
  return directory;
}

void MapServerDirectory::Poll() {
  bool ranges_changed = false;
  for (const auto& [server, info] : tiles_->MosaicInfos()) {
    if (transport::GetBounded(info.mosaic_id) != layout_.mosaic_id) continue;
    const mosaic::TileOwnership owned = transport::OwnershipFromIdl(info);
    const auto known = owners_.ranges().find(server);
    if (known != owners_.ranges().end() && known->second == owned) continue;
    spdlog::info("map server '{}' serves tile columns [{}, {}) rows [{}, {})", server,
                 owned.col_begin, owned.col_end, owned.row_begin, owned.row_end);
    owners_.Set(server, owned);
    ranges_changed = true;
  }
  if (ranges_changed || owners_.ranges().empty()) uncovered_ = owners_.UncoveredTiles(layout_);
  RefreshReachability();
}

void MapServerDirectory::RefreshReachability() {
  watch_->Poll();
  servers_.clear();
  std::vector<std::string> unreachable;
  const bool requests_read = tiles_->RequestsMatched();
  for (const auto& [server, owned] : owners_.ranges()) {
    servers_.push_back(server);
    if (!requests_read || !watch_->SeenWithin(server, timeout_)) unreachable.push_back(server);
  }
  for (const std::string& server : unreachable) {
    if (std::find(unreachable_.begin(), unreachable_.end(), server) == unreachable_.end()) {
      spdlog::warn("map server '{}' unreachable: its tiles come from the cache only", server);
    }
  }
  for (const std::string& server : unreachable_) {
    if (std::find(unreachable.begin(), unreachable.end(), server) == unreachable.end()) {
      spdlog::info("map server '{}' reachable", server);
    }
  }
  unreachable_ = std::move(unreachable);
}

bool MapServerDirectory::Reachable(const mosaic::TileKey& key) {
  RefreshReachability();
  for (const std::string& owner : owners_.OwnersOf(key)) {
    if (std::find(unreachable_.begin(), unreachable_.end(), owner) == unreachable_.end())
      return true;
  }
  return false;
}

std::string MapServerDirectory::UnreachableNames() const {
  std::string names;
  for (const std::string& server : unreachable_) names += (names.empty() ? "" : ", ") + server;
  return names;
}

}  // namespace fleetloc::tracker_agent
