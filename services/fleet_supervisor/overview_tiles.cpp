// OverviewTiles: request, wait, cache.
#include "fleet_supervisor/overview_tiles.h"

#include <spdlog/spdlog.h>

#include "transport/mosaic_messages.h"

namespace fleetloc::fleet_supervisor {

using Outcome = TileAnswer::Outcome;

OverviewTiles::OverviewTiles(std::unique_ptr<transport::TileClient> client, size_t cache_bytes,
                             std::chrono::milliseconds timeout, int min_level)
    : client_(std::move(client)),
      cache_bytes_(cache_bytes),
      timeout_(timeout),
      min_level_(min_level) {}

void OverviewTiles::Pump() {
  std::lock_guard lock(mutex_);
  PumpLocked();
}

void OverviewTiles::PumpLocked() {
  if (std::optional<fleetloc_MosaicInfo> info = client_->LatestMosaicInfo()) {
    Result<mosaic::MosaicLayout> layout = transport::LayoutFromIdl(*info);
    if (layout.ok() && (!layout_ || layout->version != layout_->version ||
                        layout->mosaic_id != layout_->mosaic_id)) {
      spdlog::info("overview: mosaic {} version {}", layout->mosaic_id, layout->version);
      layout_ = *layout;
      cache_.clear();
      lru_.clear();
      failed_.clear();
      bytes_ = 0;
    }
  }
  Result<std::vector<transport::ReceivedTile>> tiles = client_->TakeTiles();
  if (!tiles.ok()) {
    spdlog::warn("overview tiles: {}", tiles.status().message());
    return;
  }
  for (transport::ReceivedTile& tile : *tiles) {
    in_flight_.erase(tile.key);
    if (tile.status == fleetloc_TILE_OK) {
      Insert(tile.key, std::move(tile.data));
    } else {
      failed_[tile.key] = tile.error.empty() ? "the map server has no such tile" : tile.error;
    }
  }
  if (!tiles->empty()) arrived_.notify_all();
}

void OverviewTiles::Insert(const mosaic::TileKey& key, std::vector<std::uint8_t> png) {
  if (cache_.contains(key)) return;
  bytes_ += png.size();
  lru_.push_front(key);
  cache_[key] = {std::make_shared<const std::vector<std::uint8_t>>(std::move(png)), lru_.begin()};
  while (bytes_ > cache_bytes_ && lru_.size() > 1) {
    auto oldest = cache_.find(lru_.back());
    bytes_ -= oldest->second.png->size();
    cache_.erase(oldest);
    lru_.pop_back();
  }
}

std::optional<mosaic::MosaicLayout> OverviewTiles::Layout() const {
  std::lock_guard lock(mutex_);
  return layout_;
}

bool OverviewTiles::ServerMatched() const {
  std::lock_guard lock(mutex_);
  return client_->ServerMatched();
}

TileAnswer OverviewTiles::Get(const mosaic::TileKey& key) {
  std::unique_lock lock(mutex_);
  if (!layout_) return {Outcome::kNoMosaic, nullptr, "no map server has announced a mosaic", 0};
  const long long version = layout_->version;
  if (key.level < min_level_ || !transport::InGrid(*layout_, key)) {
    return {Outcome::kOutOfRange, nullptr,
            "tile " + mosaic::ToString(key) + " is not an overview tile of mosaic " +
                layout_->mosaic_id,
            version};
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout_;
  bool requested = false;
  for (;;) {
    if (auto it = cache_.find(key); it != cache_.end()) {
      lru_.splice(lru_.begin(), lru_, it->second.lru);
      return {Outcome::kOk, it->second.png, "", layout_ ? layout_->version : version};
    }
    if (auto failed = failed_.find(key); failed != failed_.end() && requested) {
      return {Outcome::kError, nullptr, failed->second, version};
    }
    if (!in_flight_.contains(key)) {
      failed_.erase(key);
      if (Status sent = client_->Request(next_request_++, layout_->mosaic_id, {key}); !sent.ok()) {
        return {Outcome::kError, nullptr, sent.message(), version};
      }
      in_flight_.insert(key);
      requested = true;
    }
    if (arrived_.wait_until(lock, std::min(deadline, std::chrono::steady_clock::now() +
                                                         std::chrono::milliseconds(20))) ==
            std::cv_status::timeout &&
        std::chrono::steady_clock::now() >= deadline) {
      in_flight_.erase(key);  // ask again next time
      return {Outcome::kTimeout, nullptr,
              "the map server did not answer for tile " + mosaic::ToString(key), version};
    }
    PumpLocked();  // in case the DDS thread is busy
    if (!layout_) return {Outcome::kNoMosaic, nullptr, "no mosaic", version};
  }
}

}  // namespace fleetloc::fleet_supervisor
