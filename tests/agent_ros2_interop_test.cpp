// The agent with the vehicle's navigation stack on another DDS vendor, the way a ROS 2 node on
// rmw_fastrtps sees the wire: an eProsima Fast DDS node (ros2_nav_stack_node) publishes the wheel
// odometry (nav_msgs/Odometry on rt/odom) and the start pose (rt/initialpose), and records what the
// agent (Cyclone DDS) sends back; the camera is Aravis's fake GigE Vision camera on 127.0.0.1.
// The node's poses (rt/fleetloc/pose, PoseWithCovarianceStamped in map) are on the simulator's
// truth with the 6×6 covariance filled from the 3×3, map → odom on rt/tf composes with the
// odometry to the same poses, and rt/diagnostics carries the agent's health.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/csv.h"
#include "live_vehicle.h"
#include "map_server_fixture.h"
#include "run_io/run.h"
#include "tracking/odometry_history.h"

namespace fleetloc {
namespace {

namespace fs = std::filesystem;
constexpr uint32_t kDomain = 126;  // 121 is metrics_scrape_test's

std::vector<std::vector<std::string>> ReadCsvRows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(AgentRos2Interop, AFastDdsNavStackFeedsOdometryAndReadsPoseTfAndDiagnostics) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("agent_ros2_interop", floor, kDomain);
  double start = 0.0;
  auto drive_ptr = testing::PlanDriveAhead(floor, 0.0005, 40, 21, &start);
  live_sim::PlannedDrive& drive = *drive_ptr;
  const fs::path& dir = server.dir();
  ASSERT_TRUE(run_io::WriteCameraJson(dir / "camera.json", drive.camera()).ok());
  {
    std::ofstream odometry(dir / "odometry.csv");
    odometry.precision(17);
    odometry << "t,x,y,theta\n";
    for (const geometry::StampedPose& s : drive.odometry())
      odometry << s.t << "," << s.pose.x << "," << s.pose.y << "," << s.pose.theta << "\n";
  }
  nlohmann::json config = testing::AravisAgentConfig("agv-21", kDomain, dir);
  // A frame cut as the stream opens (a third of runs here, on a quiet host) is a drop named for
  // issue_hold_s: 1 s, so that the diagnostics read OK for most of the 4 s drive after it.
  config["live"] = {{"issue_hold_s", 1.0}};
  std::ofstream(dir / "agent.json") << config.dump(2);
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent", {"--config", (dir / "agent.json").string()}, (dir / "agent.log").string());
  const double initial_t = start + 0.1;  // while the vehicle stands, before the camera starts
  const geometry::Pose2 truth0 = drive.TruthAt(initial_t);
  std::ostringstream initial;
  initial.precision(17);
  initial << initial_t << "," << truth0.x + 0.002 << "," << truth0.y - 0.001 << ","
          << truth0.theta + 0.003 << ",4e-6,4e-6,3e-5";
  const double until = drive.last_frame_t() + 0.6;
  runtime::ChildProcess node = testing::StartDaemon(
      "ros2_nav_stack_node",
      {"--profile", std::string(FLEETLOC_SOURCE_DIR) + "/tests/ros2_fastdds_profile.xml",
       "--domain", std::to_string(kDomain), "--odometry", (dir / "odometry.csv").string(),
       "--initial", initial.str(), "--until", std::to_string(until), "--out", dir.string()},
      (dir / "node.log").string());
  {
    testing::SleepUntilHost(start + 0.2);
    testing::FakeGigECamera camera(&drive, start - 100.0);
    ASSERT_TRUE(
        testing::Eventually([&] { return !node.Running(); }, until - camera_io::HostNow() + 10));
  }
  EXPECT_EQ(node.Wait(std::chrono::seconds(1)), 0) << testing::ReadWhole(dir / "node.log");
  EXPECT_EQ(agent.Stop(SIGTERM), 0);
  const std::string log = testing::ReadWhole(dir / "agent.log");
  EXPECT_NE(log.find("initial pose from initialpose"), std::string::npos) << log;

  // Poses at the frames' times, on the truth, with the covariance where ROS wants it.
  tracking::OdometryHistory odometry(100.0, 0.0);
  for (const geometry::StampedPose& s : drive.odometry()) ASSERT_TRUE(odometry.Add(s).ok());
  int at_frames = 0;
  int within = 0;  // 1 px, 0.05°
  std::map<double, geometry::Pose2> poses;
  for (const auto& row : ReadCsvRows(dir / "poses.csv")) {
    ASSERT_EQ(row.size(), 12u);
    const double t = std::stod(row[0]);
    EXPECT_EQ(row[1], "map");
    const geometry::Pose2 pose{std::stod(row[2]), std::stod(row[3]), std::stod(row[4])};
    poses[t] = pose;
    EXPECT_GT(std::stod(row[5]), 0.0);   // x-x
    EXPECT_GT(std::stod(row[10]), 0.0);  // yaw-yaw at [35]
    EXPECT_EQ(std::stod(row[11]), 0.0);  // z-z: planar
    const int i = drive.FrameAt(t);
    if (std::abs(t - drive.frame_t(i)) > 0.02) continue;  // the initial pose
    ++at_frames;
    const geometry::Pose2 truth = drive.sim().truth()[i].pose;
    const double error = std::hypot(pose.x - truth.x, pose.y - truth.y);
    EXPECT_LT(error, 0.005) << "t=" << t;  // no gross error
    within += error < 0.0005 &&
              std::abs(geometry::WrapAngle(pose.theta - truth.theta)) < 0.05 * M_PI / 180;
  }
  EXPECT_GE(at_frames, 35) << log;
  EXPECT_GE(within, 0.95 * at_frames) << log;
  // map → odom at a pose's time, composed with base_link in odom then, is that pose.
  int composed = 0;
  for (const auto& row : ReadCsvRows(dir / "tf.csv")) {
    ASSERT_EQ(row.size(), 6u);
    EXPECT_EQ(row[1], "map");
    EXPECT_EQ(row[2], "odom");
    const double t = std::stod(row[0]);
    const auto pose = poses.find(t);
    if (pose == poses.end()) continue;
    const geometry::Pose2 odom_in_map{std::stod(row[3]), std::stod(row[4]), std::stod(row[5])};
    const geometry::Pose2 base = odom_in_map * *odometry.At(t);
    EXPECT_NEAR(base.x, pose->second.x, 1e-9);
    EXPECT_NEAR(base.y, pose->second.y, 1e-9);
    ++composed;
  }
  EXPECT_GE(composed, 35);
  // Diagnostics: the agent's summary status, OK while tracking.
  int ok_reports = 0;
  std::map<std::string, int> reports;  // level and name: how many, for the failure message
  for (const auto& row : ReadCsvRows(dir / "diagnostics.csv")) {
    if (row.size() >= 3) ++reports[row[1] + " " + row[2]];
    if (row.size() >= 3 && row[2] == "fleetloc/agv-21" && row[1] == "0") ++ok_reports;
  }
  EXPECT_GE(ok_reports, 5) << ::testing::PrintToString(reports) << "\n"
                           << testing::ReadWhole(dir / "diagnostics.csv").substr(0, 3000) << log;
}

}  // namespace
}  // namespace fleetloc
