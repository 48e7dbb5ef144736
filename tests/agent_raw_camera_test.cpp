// A vehicle with a raw (uncalibrated) camera: the same simulated run, its frames turned into what a
// tilted, differently scaled camera of another size sees (a known homography), and camera.json's
// `raw` block describing it. The agent rectifies each frame: its published poses equal `fleetctl
// track`'s on the same raw run (to 1e-9, the same rectification) and agree with the offline
// tracker's on the original top-view frames. A camera at twice the mosaic's resolution is refused
// at start (exit 2, both values named) instead of losing every frame (issue 22).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "map_server_fixture.h"
#include "published_poses.h"
#include "run_io/run.h"
#include "transport/pose_messages.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

namespace fs = std::filesystem;
using testing::Eventually;
constexpr uint32_t kDomain = 88;
const cv::Size kRawSize(560, 440);

// Rectified pixel → raw pixel: scaled, rotated by ~1.4°, shifted, with a little perspective.
cv::Matx33d RectToRaw() { return {0.82, 0.02, 14, -0.02, 0.82, 18, 2e-5, -1e-5, 1}; }

// Rewrites `run`'s frames as the raw camera sees them and adds the `raw` block to camera.json.
void MakeRaw(const fs::path& run) {
  auto parsed = run_io::ReadRun(run);
  ASSERT_TRUE(parsed.ok()) << parsed.status().message();
  const geometry::CameraModel& model = parsed->camera.model;
  for (const run_io::FrameRef& frame : parsed->frames) {
    const cv::Mat rect = cv::imread(frame.file.string(), cv::IMREAD_GRAYSCALE);
    cv::Mat raw;
    cv::warpPerspective(rect, raw, cv::Mat(RectToRaw()), kRawSize, cv::INTER_CUBIC);
    ASSERT_TRUE(cv::imwrite(frame.file.string(), raw));
  }
  // Rectified pixel (u, v) → camera_ground (a, b) = (-(v - cy) r, -(u - cx) r) (docs/formats.md).
  const double r = model.resolution_m, cx = model.cx_px, cy = model.cy_px;
  const cv::Matx33d rect_to_ground(0, -r, cy * r, -r, 0, cx * r, 0, 0, 1);
  const cv::Matx33d h_ground = rect_to_ground * RectToRaw().inv();
  const fs::path camera_path = run / "camera.json";
  std::ifstream in(camera_path);
  nlohmann::json camera = nlohmann::json::parse(in);
  camera["raw"] = {{"K", {500.0, 0.0, 280.0, 0.0, 500.0, 220.0, 0.0, 0.0, 1.0}},
                   {"dist", {0.0, 0.0, 0.0, 0.0, 0.0}},
                   {"H_ground", std::vector<double>(h_ground.val, h_ground.val + 9)}};
  std::ofstream(camera_path) << camera.dump(2);
}

TEST(AgentRawCamera, RectifiedRawFramesTrackLikeTheTopViewOnes) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("agent_raw_camera", floor, kDomain);
  const fs::path top_view = server.dir() / "top_view", raw = server.dir() / "raw";
  ASSERT_EQ(testing::RunFleetctl("sim --mosaic " + server.mosaic_path() +
                                 " --frames 20 --seed 4 --out " + top_view.string())
                .exit_code,
            0);
  fs::copy(top_view, raw, fs::copy_options::recursive);
  MakeRaw(raw);
  const std::string poses = (server.dir() / "poses.csv").string();
  ASSERT_EQ(testing::RunFleetctl("track --mosaic " + server.mosaic_path() + " --run " +
                                 top_view.string() + " --out " + poses)
                .exit_code,
            0);
  auto expected = run_io::ReadPosesCsv(poses);
  ASSERT_TRUE(expected.ok());
  const std::string raw_poses = (server.dir() / "raw_poses.csv").string();
  const testing::CommandResult raw_track = testing::RunFleetctl(
      "track --mosaic " + server.mosaic_path() + " --run " + raw.string() + " --out " + raw_poses);
  ASSERT_EQ(raw_track.exit_code, 0) << raw_track.err;
  auto offline_raw = run_io::ReadPosesCsv(raw_poses);
  ASSERT_TRUE(offline_raw.ok());
  ASSERT_EQ(offline_raw->size(), expected->size());

  transport::Participant& p = server.participant();
  auto topic = transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  auto reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *topic, transport::Qos().Reliable().KeepAll());
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent",
      {"--run", raw.string(), "--domain", std::to_string(kDomain), "--vehicle-id", "agv-6",
       "--outbox", (server.dir() / "outbox.db").string()},
      (server.dir() / "agent.log").string());
  std::vector<transport::PoseReport> published;
  auto take = [&] { testing::TakePoses(*reader, &published); };
  ASSERT_TRUE(Eventually(
      [&] {
        take();
        return !agent.Running();
      },
      60));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  take();
  // Two resamplings (warp, rectification) blur the frames a little: the same poses to 0.1 px.
  const double px = 0.0005;
  size_t matched = 0;
  for (size_t i = 0; i < expected->size(); ++i) {
    const run_io::PoseRecord& row = (*expected)[i];
    const run_io::PoseRecord& same_raw = (*offline_raw)[i];
    const transport::PoseReport* it = testing::PoseAt(published, row.t);
    ASSERT_NE(it, nullptr) << "no published pose at frame time " << row.t;
    EXPECT_NEAR(it->base_in_map.pose.x, same_raw.pose.x, 1e-9);
    EXPECT_NEAR(it->base_in_map.pose.y, same_raw.pose.y, 1e-9);
    EXPECT_NEAR(it->base_in_map.pose.theta, same_raw.pose.theta, 1e-9);
    EXPECT_NEAR(it->base_in_map.pose.x, row.pose.x, 0.1 * px) << "t=" << row.t;
    EXPECT_NEAR(it->base_in_map.pose.y, row.pose.y, 0.1 * px) << "t=" << row.t;
    EXPECT_NEAR(it->base_in_map.pose.theta, row.pose.theta, 0.02 * M_PI / 180) << "t=" << row.t;
    EXPECT_EQ(tracking::LockStateName(it->state), std::string("tracking"));
    ++matched;
  }
  EXPECT_EQ(matched, 20u);
}

TEST(AgentRawCamera, ACameraAtTwiceTheMosaicsResolutionIsRefusedAtStart) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("agent_wrong_scale", floor, kDomain);
  const fs::path run = server.dir() / "run";
  ASSERT_EQ(testing::RunFleetctl("sim --mosaic " + server.mosaic_path() +
                                 " --frames 5 --seed 4 --out " + run.string())
                .exit_code,
            0);
  nlohmann::json camera = nlohmann::json::parse(std::ifstream(run / "camera.json"));
  ASSERT_EQ(camera["resolution"].get<double>(), 0.0005);
  camera["resolution"] = 0.001;
  std::ofstream(run / "camera.json") << camera.dump(2);
  const fs::path log = server.dir() / "agent.log";
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent",
      {"--run", run.string(), "--domain", std::to_string(kDomain), "--vehicle-id", "agv-7",
       "--outbox", (server.dir() / "outbox.db").string()},
      log.string());
  ASSERT_TRUE(Eventually([&] { return !agent.Running(); }, 30)) << testing::ReadWhole(log);
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 2);
  const std::string text = testing::ReadWhole(log);
  EXPECT_NE(text.find("camera resolution 0.001 m/px differs from the mosaic's 0.0005 m/px"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace fleetloc
