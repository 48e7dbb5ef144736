// The map servers a vehicle gets its tiles from: each server's MosaicInfo says which tile range it
// owns (the whole grid, or one region when the mosaic is split across servers), and its periodic
// ServiceHealth says it is alive. Tile requests go to every server and only a tile's owner
// answers, so what the vehicle needs to know is whose silence makes which tiles unreachable: the
// tile loader does not wait for those, tracking goes on from the cache.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "mosaic/tile_owners.h"
#include "transport/service_watch.h"
#include "transport/tile_client.h"

namespace fleetloc::tracker_agent {

class MapServerDirectory {
 public:
  // `tiles` must outlive the directory; only servers announcing the mosaic of `layout` count.
  static Result<std::unique_ptr<MapServerDirectory>> Create(
      const transport::Participant& participant, transport::TileClient* tiles,
      const mosaic::MosaicLayout& layout, std::chrono::duration<double> timeout);

  // Takes new MosaicInfos and health reports; logs servers appearing and reachability changes.
  void Poll();
  // The tile's owner (any of them, where ranges overlap) is reachable: it reads our requests and
  // reported health within the timeout. False for a tile no server owns. The health reports are
  // taken first: the tile loader asks while a frame waits for a tile, and a server that died since
  // the last Poll must not stall that frame a whole tile timeout for every tile it needs.
  bool Reachable(const mosaic::TileKey& key);
  // Every server owning part of the mosaic is reachable (and there is at least one).
  bool AllReachable() const { return !servers_.empty() && unreachable_.empty(); }
  bool AnyReachable() const { return unreachable_.size() < servers_.size(); }
  // Ids of the servers owning part of the mosaic (each keeps a replica of every patch).
  const std::vector<std::string>& servers() const { return servers_; }
  // Ids of the owning servers now unreachable, comma-separated (empty when none).
  std::string UnreachableNames() const;
  const mosaic::TileOwners& owners() const { return owners_; }
  // Level-0 tiles of the mosaic no announced server owns (recounted when a range changes). Zero:
  // every server keeping a replica of the patches is known.
  long long UncoveredTiles() const { return uncovered_; }

 private:
  MapServerDirectory(transport::TileClient* tiles, std::unique_ptr<transport::ServiceWatch> watch,
                     const mosaic::MosaicLayout& layout,
                     transport::ServiceWatch::Clock::duration timeout)
      : tiles_(tiles), watch_(std::move(watch)), layout_(layout), timeout_(timeout) {}

  // Takes the servers' health reports; logs reachability changes.
  void RefreshReachability();

  transport::TileClient* tiles_;
  std::unique_ptr<transport::ServiceWatch> watch_;
  mosaic::MosaicLayout layout_;  // the grid coverage is counted on
  transport::ServiceWatch::Clock::duration timeout_;
  mosaic::TileOwners owners_;
  long long uncovered_ = 0;
  std::vector<std::string> servers_;      // owning servers of our mosaic, by id
  std::vector<std::string> unreachable_;  // of servers_, as of the last Poll
};

}  // namespace fleetloc::tracker_agent
