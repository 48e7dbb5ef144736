// Tracker agent metric families: one lock state set, cycle histogram, outbox depth, hit ratio.
#include "tracker_agent/agent_metrics.h"

#include <gtest/gtest.h>

#include "metrics/exposition.h"

namespace fleetloc::tracker_agent {
namespace {

TEST(AgentMetrics, ExposesLockStateCycleTimesOutboxAndCache) {
  metrics::Histogram cycle(metrics::Histogram::LatencyBoundsS());
  for (double s : {0.003, 0.003, 0.012}) cycle.Observe(s);
  AgentMetricsInput in;
  in.lock_state = tracking::LockState::kCoasting;
  in.frames = 3;
  in.cycle_seconds = cycle.Snapshot();
  in.tile_round_trip_seconds = metrics::Histogram(metrics::Histogram::LatencyBoundsS()).Snapshot();
  in.cache.hits = 3;
  in.cache.misses = 1;
  in.loader.timeouts = 2;
  in.outbox_patches = 11;
  in.map_server_reachable = true;
  metrics::FamilyBuilder b(kAgentMetricPrefix, {{"vehicle_id", "agv-1"}});
  AddAgentFamilies(in, &b);
  const std::string text = metrics::ToText(b.Take());
  Result<metrics::Exposition> e = metrics::ParseExposition(text);
  ASSERT_TRUE(e.ok()) << e.status().message() << "\n" << text;
  EXPECT_EQ(*e->Value("fleetloc_agent_lock_state", {{"lock_state", "coasting"}}), 1);
  EXPECT_EQ(*e->Value("fleetloc_agent_lock_state", {{"lock_state", "tracking"}}), 0);
  EXPECT_EQ(*e->Value("fleetloc_agent_cycle_seconds_bucket", {{"le", "0.004"}}), 2);
  EXPECT_EQ(*e->Value("fleetloc_agent_cycle_seconds_count", {{"vehicle_id", "agv-1"}}), 3);
  EXPECT_EQ(*e->Value("fleetloc_agent_tile_round_trip_seconds_count"), 0);
  EXPECT_EQ(*e->Value("fleetloc_agent_tile_cache_hit_ratio"), 0.75);
  EXPECT_EQ(*e->Value("fleetloc_agent_tile_loads_total", {{"event", "timeouts"}}), 2);
  EXPECT_EQ(*e->Value("fleetloc_agent_patch_outbox_patches"), 11);
  EXPECT_EQ(*e->Value("fleetloc_agent_map_server_reachable"), 1);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
