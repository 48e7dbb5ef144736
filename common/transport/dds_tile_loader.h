// Tiles for a vehicle's MosaicView from the map server over DDS: a tile the view misses is
// requested and waited for (bounded); tiles asked for ahead of need (Prefetch) are kept when they
// arrive until the view asks for them, encoded until DecodeArrived (the caller's idle time) or
// the view's Load decodes them. Used as the MosaicView's TileLoader in the tracker agent.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mosaic/mosaic_view.h"
#include "transport/tile_client.h"

namespace fleetloc::transport {

struct DdsTileLoaderStats {
  long long requested = 0;    // tiles asked for (on demand and prefetch)
  long long received = 0;     // tiles that arrived
  long long waited = 0;       // on-demand loads that had to wait for the network
  long long timeouts = 0;     // on-demand loads that gave up (map server unreachable)
  long long unserved = 0;     // on-demand loads not waited for (server known to be unreachable)
  long long errors = 0;       // tiles answered with an error status or undecodable bytes
  long long invalidated = 0;  // tiles named by TileUpdates (Invalidate)
  long long refreshed = 0;    // invalidated tiles received again at the announced version or newer
  long long stale = 0;        // answers older than an announced version, refused and asked again
  long long reasked = 0;  // requests presumed lost (unanswered for half a timeout) and sent again
};

class DdsTileLoader {
 public:
  // `mosaic_id` and `tile_size_px` from the server's MosaicInfo; `timeout` bounds one wait.
  DdsTileLoader(TileClient* client, std::string mosaic_id, int tile_size_px,
                std::chrono::milliseconds timeout, size_t max_buffered = 256);

  // The decoded tile. NotFound for a tile the mosaic does not have (blank floor); InvalidInput
  // for an error answer or corrupt bytes; Internal when no answer came within the timeout.
  Result<cv::Mat> Load(const mosaic::TileKey& key);
  // Asks for tiles that are not already asked for or buffered, without waiting. A request left
  // unanswered for half the timeout is presumed lost and sent again: its server may have died
  // and restarted, or not yet have matched our request writer, since it was sent.
  Status Prefetch(const std::vector<mosaic::TileKey>& keys);
  // Whether the map server answering for a tile is reachable now (with the mosaic split across
  // servers, each tile has its own). A missing tile whose server is known to be unreachable is
  // still asked for but not waited for: the tracker goes on from what it has instead of stalling
  // a timeout per tile. A wait asks again every kReachabilityCheck.
  using Reachability = std::function<bool(const mosaic::TileKey&)>;
  void SetReachability(Reachability reachable) { reachable_ = std::move(reachable); }
  // The same for every tile (one map server serving them all).
  void SetServerReachable(bool reachable) {
    SetReachability([reachable](const mosaic::TileKey&) { return reachable; });
  }
  // Called with the seconds from a tile's (last) request to its answer, for every answer.
  using RoundTripObserver = std::function<void(double seconds)>;
  void SetRoundTripObserver(RoundTripObserver observer) { round_trip_ = std::move(observer); }
  // A TileUpdate announced `version` of `keys`: buffered copies are dropped, and answers older
  // than `version` for them are refused (they were in flight before the update) and asked again.
  void Invalidate(const std::vector<mosaic::TileKey>& keys, long long version);
  // Takes the tiles that arrived so far into the buffer, still encoded (Load and Prefetch do it
  // too).
  Status Poll();
  // Polls, then decodes at most `max_tiles` of the buffered encoded tiles, oldest first; returns
  // how many are left encoded. Decoding takes ~1 ms per 256 px tile: a caller with idle time
  // spends it there, so that a burst of prefetched tiles is not decoded inside a frame's cycle.
  Result<size_t> DecodeArrived(size_t max_tiles);
  size_t encoded() const { return encoded_.size(); }

  mosaic::TileLoader AsTileLoader() {
    return [this](const mosaic::TileKey& key) { return Load(key); };
  }
  const DdsTileLoaderStats& stats() const { return stats_; }
  size_t pending() const { return in_flight_.size(); }

 private:
  using Clock = std::chrono::steady_clock;
  // How often a wait asks again whether the tile's server is reachable.
  static constexpr std::chrono::milliseconds kReachabilityCheck{100};
  // A load given up on because the tile's server is unreachable (counted; asked again next time).
  Status Unserved(const mosaic::TileKey& key);
  Status Ask(const std::vector<mosaic::TileKey>& keys);
  // Whether `key` should be (re)sent: not in flight, or its request presumed lost.
  bool NeedsAsking(const mosaic::TileKey& key, Clock::time_point now);
  // An answer: round trip, version check, then buffered encoded (oldest dropped beyond the bound).
  void Receive(ReceivedTile tile);
  // Decodes a received answer into the buffer of tiles ready for the view.
  void Keep(ReceivedTile tile);
  // Decodes `key` if it is buffered encoded; true when it is ready for the view.
  bool Ready(const mosaic::TileKey& key);
  bool IsCurrent(const ReceivedTile& tile);

  TileClient* client_;
  std::string mosaic_id_;
  int tile_size_px_;
  std::chrono::milliseconds timeout_;
  size_t max_buffered_;
  uint32_t next_request_ = 1;
  std::map<mosaic::TileKey, Clock::time_point> in_flight_;  // when each was last asked for
  std::map<mosaic::TileKey, Result<cv::Mat>> arrived_;
  std::deque<mosaic::TileKey> arrival_order_;        // for the buffer bound
  std::map<mosaic::TileKey, ReceivedTile> encoded_;  // received, not decoded yet
  std::deque<mosaic::TileKey> encoded_order_;  // decoding order and its bound (may name gone keys)
  std::map<mosaic::TileKey, long long> min_version_;  // announced by TileUpdates, not yet received
  Reachability reachable_ = [](const mosaic::TileKey&) { return true; };
  DdsTileLoaderStats stats_;
  RoundTripObserver round_trip_;
};

}  // namespace fleetloc::transport
