// SharedFleet's re-mapping jobs: with the mosaic split across map servers every server runs each
// command, and the supervisor keeps (and the dashboard shows) one job per command and server.
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

}  // namespace
}  // namespace fleetloc::fleet_supervisor
