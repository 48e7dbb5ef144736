// Supervisor metric families: vehicles counted by lock state, per-vehicle health gauges, counters
// vs gauges — read back with the strict exposition parser.
#include "fleet_supervisor/supervisor_metrics.h"

#include <gtest/gtest.h>

#include "metrics/exposition.h"

namespace fleetloc::fleet_supervisor {
namespace {

fleet::PoseSample Pose(localization::LockState lock) {
  fleet::PoseSample p;
  p.t = 100;
  p.lock = lock;
  return p;
}

metrics::Exposition Parse(metrics::FamilyBuilder* b) {
  const std::string text = metrics::ToText(b->Take());
  Result<metrics::Exposition> e = metrics::ParseExposition(text);
  EXPECT_TRUE(e.ok()) << e.status().message() << "\n" << text;
  return e.ok() ? *e : metrics::Exposition{};
}

TEST(SupervisorMetrics, CountsVehiclesByLockStateAndReportsEachVehiclesHealth) {
  fleet::FleetState fleet({}, {});
  fleet.OnPose("agv-1", Pose(localization::LockState::kTracking), 100);
  fleet.OnPose("agv-2", Pose(localization::LockState::kTracking), 100);
  fleet.OnPose("agv-3", Pose(localization::LockState::kLost), 100);
  fleet::HealthSample h;
  h.cycle_ms_p95 = 12.5;
  h.patch_outbox = 17;
  h.cache_hit_rate = 0.75;
  h.map_server_reachable = false;
  fleet.OnHealth("agv-4", h, 100);  // health, no pose yet
  metrics::FamilyBuilder b(kSupervisorMetricPrefix, {{"service_id", "sup-1"}});
  AddFleetFamilies(fleet, &b);
  const metrics::Exposition e = Parse(&b);
  auto vehicles = [&](const char* state) {
    return *e.Value("fleetloc_supervisor_vehicles",
                    {{"lock_state", state}, {"service_id", "sup-1"}});
  };
  EXPECT_EQ(vehicles("tracking"), 2);
  EXPECT_EQ(vehicles("lost"), 1);
  EXPECT_EQ(vehicles("coasting"), 0);
  EXPECT_EQ(vehicles("unknown"), 1);
  EXPECT_EQ(e.types.at("fleetloc_supervisor_vehicles"), "gauge");
  const std::map<std::string, std::string> agv4 = {{"vehicle_id", "agv-4"}};
  EXPECT_EQ(*e.Value("fleetloc_supervisor_vehicle_patch_outbox_patches", agv4), 17);
  EXPECT_EQ(*e.Value("fleetloc_supervisor_vehicle_tile_cache_hit_ratio", agv4), 0.75);
  EXPECT_EQ(*e.Value("fleetloc_supervisor_vehicle_map_server_reachable", agv4), 0);
  EXPECT_NEAR(*e.Value("fleetloc_supervisor_vehicle_cycle_seconds",
                       {{"vehicle_id", "agv-4"}, {"quantile", "0.95"}}),
              0.0125, 1e-9);
  // Vehicles without health have no per-vehicle series.
  EXPECT_FALSE(
      e.Value("fleetloc_supervisor_vehicle_patch_outbox_patches", {{"vehicle_id", "agv-1"}}).ok());
}

TEST(SupervisorMetrics, QueueDepthsAreGaugesAndEventsCounters) {
  metrics::FamilyBuilder b(kSupervisorMetricPrefix, {});
  AddSupervisorFamilies({{"poses_received", 10}, {"history_queue", 3}, {"http_streams_open", 2}},
                        true, &b);
  const metrics::Exposition e = Parse(&b);
  EXPECT_EQ(e.types.at("fleetloc_supervisor_poses_received_total"), "counter");
  EXPECT_EQ(e.types.at("fleetloc_supervisor_history_queue"), "gauge");
  EXPECT_EQ(e.types.at("fleetloc_supervisor_http_streams_open"), "gauge");
  EXPECT_EQ(*e.Value("fleetloc_supervisor_poses_received_total"), 10);
  EXPECT_EQ(*e.Value("fleetloc_supervisor_map_server_alive"), 1);
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
