// SharedFleet's re-mapping jobs: with the mosaic split across map servers every server runs each
// command, and the supervisor keeps (and the dashboard shows) one job per command and server.
// A vehicle that stopped talking is STALE in every view (fleet summary, its health).
#include "fleet_supervisor/shared_fleet.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet_supervisor {
namespace {

transport::RemapProgress Status(uint64_t command, const std::string& server,
                                fleetloc_RemapState state, double t) {
  transport::RemapProgress p;
  p.command_id = command;
  p.server_id = server;
  p.state = state;
  p.t = t;
  p.new_version = state == fleetloc_REMAP_DONE ? 2 : 0;
  return p;
}

TEST(SharedFleet, KeepsOneRemapJobPerCommandAndServer) {
  SharedFleet fleet(fleet::AlertOptions{}, fleet::TrailOptions{}, 1.0);
  fleet.OnRemapStatus({Status(7, "ms-west", fleetloc_REMAP_RUNNING, 1.0),
                       Status(7, "ms-east", fleetloc_REMAP_RUNNING, 1.1)});
  fleet.OnRemapStatus({Status(7, "ms-east", fleetloc_REMAP_DONE, 2.0),
                       Status(7, "ms-west", fleetloc_REMAP_FAILED, 2.1)});
  const nlohmann::json jobs = fleet.Snapshot(3.0)["remap_jobs"];
  ASSERT_EQ(jobs.size(), 2u) << jobs.dump();
  std::map<std::string, std::string> state_by_server;
  for (const nlohmann::json& job : jobs) {
    EXPECT_EQ(job["command_id"], "7");
    state_by_server[job["server_id"]] = job["state"];
  }
  EXPECT_EQ(state_by_server["ms-east"], "done");
  EXPECT_EQ(state_by_server["ms-west"], "failed");
}

TEST(SharedFleet, AVehicleThatStoppedTalkingIsStaleInTheSummaryAndItsHealth) {
  SharedFleet fleet(fleet::AlertOptions{}, fleet::TrailOptions{}, 1.0);  // silent after 3 s
  constexpr double kT0 = 1.7e9;
  fleet::VehicleState v;
  v.id = "agv-1";
  v.pose = fleet::PoseSample{};
  v.pose->t = kT0;
  v.pose->lock = localization::LockState::kTracking;
  v.health = fleet::HealthSample{};
  v.health->t = kT0;
  v.health->level = fleet::HealthLevel::kOk;
  v.last_seen = kT0;
  fleet.Restore({v}, {});
  fleet.Evaluate(kT0 + 1.0);
  nlohmann::json now = fleet.Fleet(kT0 + 1.0, false);
  EXPECT_EQ(now["summary"]["tracking"], 1) << now.dump();
  EXPECT_EQ(now["vehicles"][0]["health"]["level"], "ok");
  fleet.Evaluate(kT0 + 4.0);
  now = fleet.Fleet(kT0 + 4.0, false);
  EXPECT_EQ(now["summary"]["tracking"], 0) << now.dump();
  EXPECT_EQ(now["summary"]["silent"], 1);
  EXPECT_EQ(now["vehicles"][0]["silent"], true);
  EXPECT_EQ(now["vehicles"][0]["health"]["level"], "stale");
  EXPECT_EQ(now["vehicles"][0]["health"]["reported_level"], "ok");
  EXPECT_EQ((*fleet.Vehicle("agv-1"))["health"]["level"], "stale");
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
