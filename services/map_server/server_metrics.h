// The map server's Prometheus metrics: its health counters, the tile reply latency histogram,
// the encoded-tile cache (hit ratio, bytes), queued tile requests and the served mosaic version.
// Pure: the server's loop gathers the input and publishes the families.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "metrics/histogram.h"
#include "metrics/metric_families.h"
#include "mosaic/tile_cache.h"

namespace fleetloc::map_server {

inline constexpr const char* kMapServerMetricPrefix = "fleetloc_map_server_";

struct MapServerMetricsInput {
  std::vector<std::pair<std::string, std::uint64_t>> counters;  // ServerCounters::Snapshot
  metrics::HistogramSnapshot tile_reply_latency;
  mosaic::TileCacheStats cache;
  std::size_t tile_requests_pending = 0;
  long long mosaic_version = 0;
};

void AddMapServerFamilies(const MapServerMetricsInput& in, metrics::FamilyBuilder* b);

}  // namespace fleetloc::map_server
