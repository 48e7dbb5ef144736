// A camera behind a GStreamer pipeline (OpenCV's GStreamer backend): multifilesrc over a
// simulated run's frames, stamped as multifilesrc stamps its buffers (frame n at n / framerate
// after the run's first frame),
// the run's odometry as ROS 2 nav_msgs/Odometry and its initial pose as initialpose. The agent's
// ROS 2 poses equal `fleetctl track`'s on the same run (to 0.01 px: the same frames, times and
// odometry go through the same tracker); through a JPEG encoder and decoder, as from a camera that
// streams MJPEG, they stay within a tenth of a pixel of the truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "live_vehicle.h"
#include "map_server_fixture.h"
#include "run_io/run.h"

namespace fleetloc {
namespace {

namespace fs = std::filesystem;
using testing::Eventually;
constexpr uint32_t kDomain = 127;      // 122 is the supervisor OpenAPI test's
constexpr uint32_t kJpegDomain = 129;  // this file's two tests may run side by side
constexpr int kFrames = 30;
constexpr double kPx = 0.0005;  // the drive's resolution, m per pixel

// A drive over the demo floor written as a run (frames, odometry, initial pose) under `dir`.
struct DriveRun {
  std::unique_ptr<live_sim::PlannedDrive> drive;
  run_io::Run run;
};

DriveRun WriteDriveRun(const cv::Mat& floor, const fs::path& run_dir) {
  const double start = 1000.0;  // the run's own clock: PTS 0 is its first frame
  DriveRun out{testing::PlanDrive(floor, kPx, kFrames, 10.0, start, 0.5, 1000.0, 22), {}};
  live_sim::PlannedDrive& drive = *out.drive;
  fs::create_directories(run_dir / "frames");
  run_io::Run& run = out.run;
  run.dir = run_dir;
  run.vehicle_id = "agv-22";
  run.camera = drive.camera();
  run.initial_pose = drive.sim().initial_pose();
  run.initial_sigma = drive.sim().initial_sigma();
  run.odometry = drive.odometry();
  for (int i = 0; i < kFrames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frames/frame_%05d.png", i);
    EXPECT_TRUE(cv::imwrite((run_dir / name).string(), drive.image(i)));
    run.frames.push_back({drive.frame_t(i), run_dir / name});
  }
  EXPECT_TRUE(run_io::WriteRun(run).ok());
  return out;
}

// The agent fed the run's frames by a multifilesrc pipeline (pngdec, then `filters` before the
// GRAY8 appsink), its odometry as ROS 2 nav_msgs/Odometry and its initial pose as initialpose:
// the newest ROS 2 pose it published at each time.
std::map<double, geometry::Pose2> AgentPoses(testing::MapServerFixture& server, const DriveRun& d,
                                             const std::string& filters) {
  const fs::path dir = server.dir(), live = dir / "live";
  fs::create_directories(live);
  const run_io::Run& run = d.run;
  const std::string pipeline = "multifilesrc location=" + (live / "frame_%05d.png").string() +
                               " index=0 stop-index=" + std::to_string(kFrames - 1) +
                               " caps=image/png,framerate=10/1 ! pngdec ! " + filters +
                               "videoconvert ! video/x-raw,format=GRAY8 ! appsink sync=true "
                               "max-buffers=1";
  const nlohmann::json config = {
      {"vehicle_id", "agv-22"},
      {"domain", server.domain()},
      {"source", "gstreamer"},
      {"camera", (run.dir / "camera.json").string()},
      {"outbox", (dir / "outbox.db").string()},
      {"drain_s", 0.0},
      {"live", {{"frame_queue", 64}, {"odometry_stale_s", 30.0}}},
      {"ros", {{"odom_history", 5000}}},
      {"gstreamer",
       {{"pipeline", pipeline}, {"timestamps", "frame_rate"}, {"epoch_s", d.drive->frame_t(0)}}}};
  std::ofstream(dir / "agent.json") << config.dump(2);
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent", {"--config", (dir / "agent.json").string()}, (dir / "agent.log").string());
  transport::Participant& p = server.participant();
  using PoseMsg = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;
  testing::RosPoseEndpoints ros(p);
  auto& pose_reader = ros.poses;
  auto& init_writer = ros.initial_pose;
  std::map<double, geometry::Pose2> poses;
  EXPECT_TRUE(Eventually([&] { return init_writer->MatchedReaders() > 0; }, 30));
  {
    auto odometry = testing::PublishOdometry(p, run.odometry, nullptr, 0.0005);
    EXPECT_TRUE(Eventually([&] { return odometry->done(); }, 20));
  }
  // The run's initial pose, at its first frame; then the frames appear for the pipeline.
  const Eigen::Vector3d sigma = run.initial_sigma;
  const transport::RosPoseMessage initial(
      d.drive->frame_t(0), "map", {run.initial_pose, sigma.cwiseProduct(sigma).asDiagonal()});
  EXPECT_TRUE(init_writer->Write(initial.get()).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (const run_io::FrameRef& frame : run.frames)
    fs::copy_file(frame.file, live / frame.file.filename());
  auto frames_seen = [&] {
    (void)pose_reader->TakeAll([&](const PoseMsg& m, const dds_sample_info_t&) {
      const transport::RosPoseStamped pose = transport::FromIdl(m);
      poses[pose.t] = pose.pose.pose;  // the newest at a time
    });
    return poses.size() >= static_cast<size_t>(kFrames);  // the initial pose is at frame 0's time
  };
  EXPECT_TRUE(Eventually(frames_seen, 30)) << testing::ReadWhole(dir / "agent.log");
  EXPECT_EQ(agent.Stop(SIGTERM), 0);
  return poses;
}

// The pose published at `t` (to a microsecond), or nullopt.
std::optional<geometry::Pose2> PoseAt(const std::map<double, geometry::Pose2>& poses, double t) {
  const auto it = poses.lower_bound(t - 1e-6);
  if (it == poses.end() || std::abs(it->first - t) >= 1e-6) return std::nullopt;
  return it->second;  // frame 0's tracked pose replaced the initial one
}

// `fleetctl track`'s poses over the drive's run, as written (no codec in between).
Result<std::vector<run_io::PoseRecord>> OfflinePoses(testing::MapServerFixture& server,
                                                     const DriveRun& d) {
  const fs::path offline = server.dir() / "poses.csv";
  EXPECT_EQ(testing::RunFleetctl("track --mosaic " + server.mosaic_path() + " --run " +
                                 d.run.dir.string() + " --out " + offline.string())
                .exit_code,
            0);
  return run_io::ReadPosesCsv(offline);
}

cv::Mat DemoFloor() {
  return cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                    cv::IMREAD_GRAYSCALE);
}

TEST(AgentGstreamer, AMultifilesrcPipelineTracksLikeTheOfflineTracker) {
  const cv::Mat floor = DemoFloor();
  testing::MapServerFixture server("agent_gstreamer", floor, kDomain);
  const DriveRun d = WriteDriveRun(floor, server.dir() / "run");
  const auto expected = OfflinePoses(server, d);
  ASSERT_TRUE(expected.ok());
  const std::map<double, geometry::Pose2> poses = AgentPoses(server, d, "");
  int matched = 0;
  for (const run_io::PoseRecord& row : *expected) {
    const std::optional<geometry::Pose2> pose = PoseAt(poses, row.t);
    ASSERT_TRUE(pose) << "no pose at t=" << row.t << ", have " << ::testing::PrintToString(poses);
    EXPECT_NEAR(pose->x, row.pose.x, 0.01 * kPx) << "t=" << row.t;
    EXPECT_NEAR(pose->y, row.pose.y, 0.01 * kPx) << "t=" << row.t;
    EXPECT_NEAR(pose->theta, row.pose.theta, 1e-6) << "t=" << row.t;
    EXPECT_EQ(row.status, "tracking");
    ++matched;
  }
  EXPECT_EQ(matched, kFrames);
}

// A camera that streams JPEG (MJPEG, as many USB and IP cameras do): the frames pass through
// GStreamer's jpegenc at quality 70 and jpegdec, 8 × 8 block artifacts and all, before the
// agent sees them. Every frame's pose is within a tenth of a pixel of the truth.
TEST(AgentGstreamer, AJpegStreamingCameraTracksWithinATenthOfAPixel) {
  const cv::Mat floor = DemoFloor();
  testing::MapServerFixture server("agent_gstreamer_jpeg", floor, kJpegDomain);
  const DriveRun d = WriteDriveRun(floor, server.dir() / "run");
  const auto uncompressed = OfflinePoses(server, d);
  ASSERT_TRUE(uncompressed.ok());
  const std::map<double, geometry::Pose2> poses =
      AgentPoses(server, d, "videoconvert ! jpegenc quality=70 ! jpegdec ! ");
  double most_moved = 0;  // by the compression: the largest change from the uncompressed frames'
  for (const run_io::PoseRecord& row : *uncompressed) {
    const std::optional<geometry::Pose2> pose = PoseAt(poses, row.t);
    ASSERT_TRUE(pose) << "no pose at t=" << row.t;
    const geometry::Pose2 truth = d.drive->TruthAt(row.t);
    EXPECT_LT(std::hypot(pose->x - truth.x, pose->y - truth.y), 0.1 * kPx) << "t=" << row.t;
    most_moved = std::max(most_moved, std::hypot(pose->x - row.pose.x, pose->y - row.pose.y));
  }
  EXPECT_GT(most_moved, 0.005 * kPx);  // the frames went through the codec (0.013 px here)
}

}  // namespace
}  // namespace fleetloc
