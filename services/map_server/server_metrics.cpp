// Map server metric families.
#include "map_server/server_metrics.h"

namespace fleetloc::map_server {

void AddMapServerFamilies(const MapServerMetricsInput& in, metrics::FamilyBuilder* b) {
  b->HealthCounters(in.counters, {});
  b->Histogram("tile_reply_seconds", "From a tile request's arrival to its last tile written",
               in.tile_reply_latency);
  const long long lookups = in.cache.hits + in.cache.misses;
  b->Gauge("tile_cache_hit_ratio",
           "Encoded-tile cache hits / lookups since start (1 before any lookup)",
           lookups > 0 ? static_cast<double>(in.cache.hits) / static_cast<double>(lookups) : 1.0);
  b->Counter("tile_cache_hits", "Encoded-tile cache hits", static_cast<double>(in.cache.hits));
  b->Counter("tile_cache_misses", "Encoded-tile cache misses (read from SQLite)",
             static_cast<double>(in.cache.misses));
  b->Gauge("tile_cache_bytes", "Encoded tile bytes cached", static_cast<double>(in.cache.bytes));
  b->Gauge("tile_requests_pending", "Tile requests waiting for their vehicle's reader to match",
           static_cast<double>(in.tile_requests_pending));
  b->Gauge("mosaic_version", "The mosaic version served", static_cast<double>(in.mosaic_version));
}

}  // namespace fleetloc::map_server
