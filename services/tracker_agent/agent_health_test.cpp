// The agent's health: issues about counts are news for the hold, the counts stay in the figures.
#include "tracker_agent/agent_health.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "transport/wire_util.h"

namespace fleetloc::tracker_agent {
namespace {

struct Report {
  fleetloc_HealthLevel level;
  std::vector<std::string> issues;
  uint64_t frame_drops;
};

Report Take(AgentHealth* health, const AgentHealth::Inputs& in) {
  fleetloc_VehicleHealth h{};
  std::vector<fleetloc_HealthIssue> storage;
  health->Fill(in, &h, &storage);
  Report r{h.level, {}, h.camera_frame_drops};
  for (const fleetloc_HealthIssue& issue : storage)
    r.issues.push_back(transport::GetBounded(issue.name));
  return r;
}

bool Names(const Report& r, const std::string& issue) {
  return std::find(r.issues.begin(), r.issues.end(), issue) != r.issues.end();
}

TEST(AgentHealth, ACountsIssueHoldsAfterItRoseThenClearsWhileTheCountStays) {
  AgentHealth health(2.0);
  health.RecordLockState(tracking::LockState::kTracking);
  AgentHealth::Inputs in;
  in.map_server_reachable = true;
  in.host_s = 100.0;
  EXPECT_EQ(Take(&health, in).level, fleetloc_HEALTH_OK);

  health.RecordDroppedFrame("the tracker is behind");
  in.input_dropped = 2;  // and two frames the camera lost
  in.loader.timeouts = 1;
  in.patch_outbox_dropped = 3;
  in.host_s = 100.5;
  Report r = Take(&health, in);
  EXPECT_EQ(r.level, fleetloc_HEALTH_WARN);
  for (const char* issue : {"camera_frame_drops", "tile_timeouts", "patch_outbox_full"})
    EXPECT_TRUE(Names(r, issue)) << issue;
  EXPECT_EQ(r.frame_drops, 3u);

  in.host_s = 102.4;  // held
  EXPECT_EQ(Take(&health, in).issues.size(), 3u);
  in.host_s = 102.6;  // no count rose for 2 s: news no longer, the figure still counts them
  r = Take(&health, in);
  EXPECT_EQ(r.level, fleetloc_HEALTH_OK);
  EXPECT_TRUE(r.issues.empty());
  EXPECT_EQ(r.frame_drops, 3u);

  in.loader.timeouts = 2;  // one more timeout: that issue alone again
  in.host_s = 200.0;
  r = Take(&health, in);
  EXPECT_EQ(r.issues, std::vector<std::string>{"tile_timeouts"});
}

}  // namespace
}  // namespace fleetloc::tracker_agent
