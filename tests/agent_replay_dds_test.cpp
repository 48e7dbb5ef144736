// The tracker agent live over DDS: a map_server process and a tracker_agent process on their own
// domain; the poses the agent publishes for a replayed simulated run equal `fleetctl track`'s
// offline output on the same run (same frames, same numbers to 1e-9) and meet its accuracy; it
// also reports its health.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "map_server_fixture.h"
#include "published_poses.h"
#include "run_io/run.h"
#include "transport/pose_messages.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 84;

TEST(AgentReplayDds, PublishedPosesEqualTheOfflineTrackerAndHealthIsReported) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("agent_replay_dds", floor, kDomain);
  const std::string run = (server.dir() / "run").string();
  const std::string poses = (server.dir() / "poses.csv").string();
  ASSERT_EQ(testing::RunFleetctl("sim --mosaic " + server.mosaic_path() +
                                 " --frames 25 --seed 3 --out " + run)
                .exit_code,
            0);
  const testing::CommandResult offline = testing::RunFleetctl(
      "track --mosaic " + server.mosaic_path() + " --run " + run + " --out " + poses);
  ASSERT_EQ(offline.exit_code, 0) << offline.err;
  auto expected = run_io::ReadPosesCsv(poses);
  ASSERT_TRUE(expected.ok());

  transport::Participant& p = server.participant();
  auto pose_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  auto health_topic =
      transport::Topic<fleetloc_VehicleHealth>::Create(p, transport::topics::kVehicleHealth);
  auto pose_reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *pose_topic, transport::Qos().Reliable().KeepAll());
  auto health_reader = transport::VehicleStreamReader<fleetloc_VehicleHealth>::Create(
      p, *health_topic, transport::Qos().Reliable().KeepAll());
  runtime::ChildProcess agent =
      testing::StartDaemon("tracker_agent",
                           {"--run", run, "--domain", std::to_string(kDomain), "--vehicle-id",
                            "agv-7", "--outbox", (server.dir() / "outbox.db").string()},
                           (server.dir() / "agent.log").string());
  std::vector<transport::PoseReport> published;
  int health_reports = 0;
  bool reachable = false;
  ASSERT_TRUE(Eventually(
      [&] {
        testing::TakePoses(*pose_reader, &published);
        (void)health_reader->TakeAll(
            [&](const fleetloc_VehicleHealth& h, const dds_sample_info_t&) {
              ++health_reports;
              reachable = reachable || h.map_server_reachable;
            });
        return !agent.Running();
      },
      60));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  testing::TakePoses(*pose_reader, &published);
  // Every frame's pose, at the frame's time, equal to the offline tracker's.
  size_t matched = 0;
  for (const run_io::PoseRecord& row : *expected) {
    const transport::PoseReport* it = testing::PoseAt(published, row.t);
    ASSERT_NE(it, nullptr) << "no published pose at frame time " << row.t;
    EXPECT_NEAR(it->base_in_map.pose.x, row.pose.x, 1e-9);
    EXPECT_NEAR(it->base_in_map.pose.y, row.pose.y, 1e-9);
    EXPECT_NEAR(it->base_in_map.pose.theta, row.pose.theta, 1e-9);
    EXPECT_LT((it->base_in_map.covariance - row.covariance).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_EQ(tracking::LockStateName(it->state), row.status);
    ++matched;
  }
  EXPECT_EQ(matched, 25u);
  // Between frames, odometry-rate poses (100 Hz odometry over ~5 s).
  EXPECT_GT(published.size(), 300u);
  // The offline run's accuracy, which the live poses share.
  const auto summary = nlohmann::json::parse(offline.out);
  EXPECT_GE(summary["lock_rate"].get<double>(), 0.99) << offline.out;
  EXPECT_GE(health_reports, 3);
  EXPECT_TRUE(reachable);
}

}  // namespace
}  // namespace fleetloc
