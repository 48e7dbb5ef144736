// Answers TileRequests: each requested tile is read from the store and written, with its status,
// to the requesting vehicle's partition. Bad requests are answered with an error status where an
// answer is possible, counted, and logged; they never stop the service.
#pragma once

#include <chrono>
#include <deque>
#include <string>
#include <vector>

#include "map_server/pending_replies.h"
#include "map_server/server_counters.h"
#include "map_server/vehicle_channels.h"
#include "metrics/histogram.h"
#include "mosaic/tile_cache.h"
#include "mosaic/tile_ownership.h"
#include "mosaic/tile_store.h"

namespace fleetloc::map_server {

class TileService {
 public:
  // The counter names this service uses (for ServerCounters).
  static std::vector<std::string> CounterNames();

  // `cache_bytes` bounds the encoded tiles kept in memory (a fleet on one floor asks for the same
  // tiles again and again; the cache spares SQLite reads and copies).
  TileService(mosaic::TileStore* store, mosaic::TileOwnership owned, VehicleChannels* channels,
              ServerCounters* counters, int max_tiles_per_request, size_t cache_bytes);

  // Queues a received request (copied: the sample is a DDS loan).
  void Receive(const fleetloc_TileRequest& request);
  // Answers the queued requests whose vehicle's reader is matched; drops (and counts) requests
  // that waited longer than `match_timeout` for the vehicle to match.
  void AnswerPending(std::chrono::steady_clock::duration match_timeout = std::chrono::seconds(5));
  size_t pending() const { return pending_.size(); }
  // Forgets every cached tile (after the store moved to a new mosaic version).
  void DropCache() { cache_.Clear(); }
  mosaic::TileCacheStats cache_stats() const { return cache_.stats(); }
  // Seconds from a request's arrival to its last tile written (answered requests only).
  const metrics::Histogram& reply_latency() const { return reply_latency_; }

 private:
  struct Request {
    std::string vehicle_id;
    uint32_t request_id = 0;
    std::string mosaic_id;
    std::vector<mosaic::TileKey> tiles;
    std::chrono::steady_clock::time_point received;
  };
  void Answer(const Request& request, VehicleChannel& channel);
  // One Tile reply for `key` (status and bytes filled in); `bytes` keeps the payload alive.
  fleetloc_Tile Reply(const Request& request, const mosaic::TileKey& key, mosaic::TilePtr* bytes);
  // The encoded tile from the cache or the store (then cached).
  Result<mosaic::TilePtr> EncodedTile(const mosaic::TileKey& key);

  mosaic::TileStore* store_;
  mosaic::TileOwnership owned_;
  VehicleChannels* channels_;
  ServerCounters* counters_;
  int max_tiles_per_request_;
  PendingReplies<Request> pending_;
  mosaic::TileCache cache_;  // encoded tiles as 1×N CV_8U rows
  metrics::Histogram reply_latency_{metrics::Histogram::LatencyBoundsS()};
};

}  // namespace fleetloc::map_server
