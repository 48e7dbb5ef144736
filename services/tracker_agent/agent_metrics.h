// The tracker agent's Prometheus metrics: lock state, frames, the tracker cycle-time and tile
// round-trip histograms, tile cache hit ratio and loader counters, the patch outbox depth, map
// server reachability and relocalization attempts. Pure: the agent's loop gathers the input.
#pragma once

#include <cstddef>

#include "metrics/histogram.h"
#include "metrics/metric_families.h"
#include "mosaic/tile_cache.h"
#include "tracking/frame_localizer.h"
#include "transport/dds_tile_loader.h"

namespace fleetloc::tracker_agent {

inline constexpr const char* kAgentMetricPrefix = "fleetloc_agent_";

struct AgentMetricsInput {
  tracking::LockState lock_state = tracking::LockState::kLost;
  long long frames = 0;
  metrics::HistogramSnapshot cycle_seconds;
  metrics::HistogramSnapshot tile_round_trip_seconds;
  mosaic::TileCacheStats cache;
  transport::DdsTileLoaderStats loader;
  std::size_t tiles_pending = 0;
  long long outbox_patches = 0;
  long long outbox_dropped = 0;
  bool map_server_reachable = false;
  long long relocalization_attempts = 0, relocalization_found = 0;
};

void AddAgentFamilies(const AgentMetricsInput& in, metrics::FamilyBuilder* b);

}  // namespace fleetloc::tracker_agent
