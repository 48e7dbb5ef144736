// On-demand and prefetched tiles over DDS.
#include "transport/dds_tile_loader.h"

#include <thread>

#include "mosaic/tile_codec.h"

namespace fleetloc::transport {

DdsTileLoader::DdsTileLoader(TileClient* client, std::string mosaic_id, int tile_size_px,
                             std::chrono::milliseconds timeout, size_t max_buffered)
    : client_(client),
      mosaic_id_(std::move(mosaic_id)),
      tile_size_px_(tile_size_px),
      timeout_(timeout),
      max_buffered_(max_buffered) {}

Status DdsTileLoader::Ask(const std::vector<mosaic::TileKey>& keys) {
  for (size_t begin = 0; begin < keys.size(); begin += 256) {
    const std::vector<mosaic::TileKey> batch(keys.begin() + begin,
                                             keys.begin() + std::min(keys.size(), begin + 256));
    FLEETLOC_RETURN_IF_ERROR(client_->Request(next_request_++, mosaic_id_, batch));
    const Clock::time_point now = Clock::now();
    for (const mosaic::TileKey& key : batch) in_flight_[key] = now;
    stats_.requested += static_cast<long long>(batch.size());
  }
  return Status::Ok();
}

void DdsTileLoader::Invalidate(const std::vector<mosaic::TileKey>& keys, long long version) {
  for (const mosaic::TileKey& key : keys) {
    arrived_.erase(key);  // arrival_order_ may still name it; the bound loop tolerates that
    encoded_.erase(key);
    long long& needed = min_version_[key];
    needed = std::max(needed, version);
    ++stats_.invalidated;
  }
}

// False (and the tile forgotten, to be asked again) when a TileUpdate said a newer version exists.
bool DdsTileLoader::IsCurrent(const ReceivedTile& tile) {
  auto it = min_version_.find(tile.key);
  if (it == min_version_.end()) return true;
  if (tile.status == fleetloc_TILE_OK && tile.version < it->second) {
    ++stats_.stale;
    return false;
  }
  ++stats_.refreshed;
  min_version_.erase(it);
  return true;
}

void DdsTileLoader::Receive(ReceivedTile tile) {
  ++stats_.received;
  if (auto asked = in_flight_.find(tile.key); asked != in_flight_.end()) {
    if (round_trip_)
      round_trip_(std::chrono::duration<double>(Clock::now() - asked->second).count());
    in_flight_.erase(asked);
  }
  if (!IsCurrent(tile)) return;
  const mosaic::TileKey key = tile.key;
  if (encoded_.insert_or_assign(key, std::move(tile)).second) encoded_order_.push_back(key);
  while (encoded_order_.size() > max_buffered_) {  // oldest first (decoded ones are gone)
    encoded_.erase(encoded_order_.front());
    encoded_order_.pop_front();
  }
}

bool DdsTileLoader::Ready(const mosaic::TileKey& key) {
  if (auto it = encoded_.find(key); it != encoded_.end()) {
    ReceivedTile tile = std::move(it->second);
    encoded_.erase(it);
    Keep(std::move(tile));
  }
  return arrived_.count(key) > 0;
}

Result<size_t> DdsTileLoader::DecodeArrived(size_t max_tiles) {
  FLEETLOC_RETURN_IF_ERROR(Poll());
  for (size_t decoded = 0; decoded < max_tiles && !encoded_order_.empty();) {
    const mosaic::TileKey key = encoded_order_.front();
    encoded_order_.pop_front();
    if (encoded_.count(key)) {
      (void)Ready(key);
      ++decoded;
    }
  }
  return encoded_.size();
}

void DdsTileLoader::Keep(ReceivedTile tile) {
  Result<cv::Mat> decoded =
      NotFound("tile " + mosaic::ToString(tile.key) + " is not in the mosaic");
  if (tile.status == fleetloc_TILE_OK) {
    decoded = mosaic::DecodeTile(tile.data, tile_size_px_);
  } else if (tile.status != fleetloc_TILE_NOT_FOUND) {
    decoded = InvalidInput("tile " + mosaic::ToString(tile.key) + ": " + tile.error);
  }
  if (!decoded.ok() && decoded.status().code() != StatusCode::kNotFound) ++stats_.errors;
  if (arrived_.insert_or_assign(tile.key, std::move(decoded)).second)
    arrival_order_.push_back(tile.key);
  while (arrival_order_.size() > max_buffered_) {  // oldest first (consumed ones are gone)
    arrived_.erase(arrival_order_.front());
    arrival_order_.pop_front();
  }
}

bool DdsTileLoader::NeedsAsking(const mosaic::TileKey& key, Clock::time_point now) {
  auto it = in_flight_.find(key);
  if (it == in_flight_.end()) return true;
  if (now - it->second < timeout_ / 2) return false;
  ++stats_.reasked;
  return true;
}

Status DdsTileLoader::Poll() {
  Result<std::vector<ReceivedTile>> tiles = client_->TakeTiles();
  if (!tiles.ok()) return tiles.status();
  for (ReceivedTile& tile : *tiles) {
    if (tile.mosaic_id == mosaic_id_) Receive(std::move(tile));
  }
  return Status::Ok();
}

Status DdsTileLoader::Prefetch(const std::vector<mosaic::TileKey>& keys) {
  FLEETLOC_RETURN_IF_ERROR(Poll());
  std::vector<mosaic::TileKey> wanted;
  const Clock::time_point now = Clock::now();
  for (const mosaic::TileKey& key : keys) {
    if (!arrived_.count(key) && !encoded_.count(key) && NeedsAsking(key, now))
      wanted.push_back(key);
  }
  return Ask(wanted);
}

Result<cv::Mat> DdsTileLoader::Load(const mosaic::TileKey& key) {
  FLEETLOC_RETURN_IF_ERROR(Poll());
  if (!Ready(key)) {
    ++stats_.waited;
    if (NeedsAsking(key, Clock::now())) FLEETLOC_RETURN_IF_ERROR(Ask({key}));
    if (!reachable_(key)) return Unserved(key);
    const auto deadline = Clock::now() + timeout_;
    auto next_check = Clock::now() + kReachabilityCheck;
    while (!Ready(key)) {
      // Asked again when a stale answer came (no longer in flight) or the request seems lost.
      const Clock::time_point now = Clock::now();
      if (NeedsAsking(key, now)) FLEETLOC_RETURN_IF_ERROR(Ask({key}));
      if (now >= deadline) {
        ++stats_.timeouts;
        in_flight_.erase(key);  // ask again next time
        return Internal("tile " + mosaic::ToString(key) + ": no answer from the map server in " +
                        std::to_string(timeout_.count()) + " ms");
      }
      // A server that dies while a frame waits is given up on once its silence says so, not
      // after a whole timeout per tile the frame still needs from it.
      if (now >= next_check) {
        if (!reachable_(key)) return Unserved(key);
        next_check = now + kReachabilityCheck;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      FLEETLOC_RETURN_IF_ERROR(Poll());
    }
  }
  auto it = arrived_.find(key);
  Result<cv::Mat> tile = std::move(it->second);
  arrived_.erase(it);  // the view's cache keeps it from now on
  return tile;
}

Status DdsTileLoader::Unserved(const mosaic::TileKey& key) {
  ++stats_.unserved;
  in_flight_.erase(key);  // ask again next time
  return Internal("tile " + mosaic::ToString(key) + ": the map server is unreachable");
}

}  // namespace fleetloc::transport
