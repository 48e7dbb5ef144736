// A camera behind a GStreamer pipeline (OpenCV's GStreamer backend): multifilesrc over a
// simulated run's frames, stamped as multifilesrc stamps its buffers (frame n at n / framerate
// after the run's first frame),
// the run's odometry as ROS 2 nav_msgs/Odometry and its initial pose as initialpose. The agent's
// ROS 2 poses equal `fleetctl track`'s on the same run (to 0.01 px: the same frames, times and
// odometry go through the same tracker).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "live_vehicle.h"
#include "map_server_fixture.h"
#include "run_io/run.h"

namespace fleetloc {
namespace {

namespace fs = std::filesystem;
using testing::Eventually;
constexpr uint32_t kDomain = 127;  // 122 is the supervisor OpenAPI test's
constexpr int kFrames = 30;

TEST(AgentGstreamer, AMultifilesrcPipelineTracksLikeTheOfflineTracker) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("agent_gstreamer", floor, kDomain);
  const double start = 1000.0;  // the run's own clock: PTS 0 is its first frame
  auto drive_ptr = testing::PlanDrive(floor, 0.0005, kFrames, 10.0, start, 0.5, 1000.0, 22);
  live_sim::PlannedDrive& drive = *drive_ptr;
  const fs::path dir = server.dir(), run_dir = dir / "run", live = dir / "live";
  fs::create_directories(run_dir / "frames");
  fs::create_directories(live);
  run_io::Run run;
  run.dir = run_dir;
  run.vehicle_id = "agv-22";
  run.camera = drive.camera();
  run.initial_pose = drive.sim().initial_pose();
  run.initial_sigma = drive.sim().initial_sigma();
  run.odometry = drive.odometry();
  for (int i = 0; i < kFrames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frames/frame_%05d.png", i);
    ASSERT_TRUE(cv::imwrite((run_dir / name).string(), drive.image(i)));
    run.frames.push_back({drive.frame_t(i), run_dir / name});
  }
  ASSERT_TRUE(run_io::WriteRun(run).ok());
  const fs::path offline = dir / "poses.csv";
  ASSERT_EQ(testing::RunFleetctl("track --mosaic " + server.mosaic_path() + " --run " +
                                 run_dir.string() + " --out " + offline.string())
                .exit_code,
            0);
  auto expected = run_io::ReadPosesCsv(offline);
  ASSERT_TRUE(expected.ok());

  const std::string pipeline = "multifilesrc location=" + (live / "frame_%05d.png").string() +
                               " index=0 stop-index=" + std::to_string(kFrames - 1) +
                               " caps=image/png,framerate=10/1 ! pngdec ! videoconvert ! "
                               "video/x-raw,format=GRAY8 ! appsink sync=true max-buffers=1";
  const nlohmann::json config = {
      {"vehicle_id", "agv-22"},
      {"domain", kDomain},
      {"source", "gstreamer"},
      {"camera", (run_dir / "camera.json").string()},
      {"outbox", (dir / "outbox.db").string()},
      {"drain_s", 0.0},
      {"live", {{"frame_queue", 64}, {"odometry_stale_s", 30.0}}},
      {"ros", {{"odom_history", 5000}}},
      {"gstreamer",
       {{"pipeline", pipeline}, {"timestamps", "frame_rate"}, {"epoch_s", drive.frame_t(0)}}}};
  std::ofstream(dir / "agent.json") << config.dump(2);
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent", {"--config", (dir / "agent.json").string()}, (dir / "agent.log").string());
  transport::Participant& p = server.participant();
  using PoseMsg = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;
  testing::RosPoseEndpoints ros(p);
  auto& pose_reader = ros.poses;
  auto& init_writer = ros.initial_pose;
  ASSERT_TRUE(Eventually([&] { return init_writer->MatchedReaders() > 0; }, 30));
  {
    auto odometry = testing::PublishOdometry(p, run.odometry, nullptr, 0.0005);
    ASSERT_TRUE(Eventually([&] { return odometry->done(); }, 20));
  }
  // The run's initial pose, at its first frame; then the frames appear for the pipeline.
  const Eigen::Vector3d sigma = run.initial_sigma;
  const transport::RosPoseMessage initial(
      drive.frame_t(0), "map", {run.initial_pose, sigma.cwiseProduct(sigma).asDiagonal()});
  ASSERT_TRUE(init_writer->Write(initial.get()).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (const run_io::FrameRef& frame : run.frames)
    fs::copy_file(frame.file, live / frame.file.filename());

  std::map<double, geometry::Pose2> poses;
  auto frames_seen = [&] {
    (void)pose_reader->TakeAll([&](const PoseMsg& m, const dds_sample_info_t&) {
      const transport::RosPoseStamped pose = transport::FromIdl(m);
      poses[pose.t] = pose.pose.pose;  // the newest at a time
    });
    return poses.size() >= static_cast<size_t>(kFrames);  // the initial pose is at frame 0's time
  };
  EXPECT_TRUE(Eventually(frames_seen, 30)) << testing::ReadWhole(dir / "agent.log");
  EXPECT_EQ(agent.Stop(SIGTERM), 0);
  const double px = 0.0005;
  int matched = 0;
  for (const run_io::PoseRecord& row : *expected) {
    const auto it = poses.lower_bound(row.t - 1e-6);
    ASSERT_TRUE(it != poses.end() && std::abs(it->first - row.t) < 1e-6)
        << "no pose at t=" << row.t << ", have " << ::testing::PrintToString(poses);
    const geometry::Pose2& pose = it->second;  // frame 0's tracked pose replaced the initial one
    EXPECT_NEAR(pose.x, row.pose.x, 0.01 * px) << "t=" << row.t;
    EXPECT_NEAR(pose.y, row.pose.y, 0.01 * px) << "t=" << row.t;
    EXPECT_NEAR(pose.theta, row.pose.theta, 1e-6) << "t=" << row.t;
    EXPECT_EQ(row.status, "tracking");
    ++matched;
  }
  EXPECT_EQ(matched, kFrames);
}

}  // namespace
}  // namespace fleetloc
