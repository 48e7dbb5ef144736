// Multi-frame relocalization in the live agent (issue 17): a map_server process serves a floor
// that repeats itself — a part of a photograph twice side by side between two other strips — and
// a tracker_agent starts without a pose on a replayed drive from the first copy into the second.
// Each frame alone lies wholly inside one copy and has two true answers: the agent must refuse
// it as ambiguous, never publish a pose from it. Two frames with the odometry between them fit
// only one place: the agent must find the pose from them, then track, every published pose within
// millimetres of the truth. The map server reports the floor's twin places in its health.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "map_server_fixture.h"
#include "published_poses.h"
#include "run_io/run.h"
#include "sim/camera_renderer.h"
#include "sim/run_simulator.h"
#include "transport/place_index_channel.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 104;
constexpr double kResolutionM = 0.0005;

// [strip X | copy | copy | strip Y] of the moss photograph, 1.4 m × 0.8 m: the copies (0.5 m
// each) meet at x = 0.7 m.
cv::Mat RepeatedFloor() {
  const cv::Mat photo = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/moss_2560x1600.jpg",
                                   cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(photo.empty());
  const cv::Mat copy = photo(cv::Rect(0, 0, 1000, 1600));
  cv::Mat floor;
  cv::hconcat(std::vector<cv::Mat>{photo(cv::Rect(1000, 0, 400, 1600)), copy, copy,
                                   photo(cv::Rect(1400, 0, 400, 1600))},
              floor);
  return floor;
}

// The drive: camera (frame centre) heading +x along y = 0.4 m; the first frame inside the left
// copy (x 0.45: its frame spans x 0.33–0.57), the second 0.4 m on inside the right copy
// (0.85: 0.73–0.97), then 5 cm a frame to x 1.2 (still inside the right copy and the strip).
// Odometry 2 % long. Frames at 5 Hz, odometry at 50 Hz.
run_io::Run WriteDrive(const std::filesystem::path& dir, const cv::Mat& floor_image) {
  run_io::Run run;
  run.dir = dir;
  run.vehicle_id = "agv-6";
  run.camera.model = sim::DefaultSimCameraModel(640, 480, kResolutionM);
  const geometry::CameraModel& camera = run.camera.model;
  std::vector<double> camera_x = {0.45, 0.85};
  for (double x = 0.90; x < 1.2001; x += 0.05) camera_x.push_back(x);
  mosaic::ImageRasterSource floor(floor_image,
                                  {0.0, floor_image.rows * kResolutionM, kResolutionM});
  sim::CameraRenderer renderer(&floor, camera, sim::RenderOptions{}, 31);
  std::filesystem::create_directories(dir / "frames");
  std::vector<geometry::StampedPose> truth;
  for (std::size_t k = 0; k < camera_x.size(); ++k) {
    const double t = 0.2 * static_cast<double>(k);
    const geometry::Pose2 base = geometry::Pose2{camera_x[k], 0.4, 0.0} * camera.mount.Inverse();
    truth.push_back({t, base});
    const std::filesystem::path file = dir / "frames" / (std::to_string(k) + ".png");
    EXPECT_TRUE(cv::imwrite(file.string(), renderer.Render(base, {0, 0}, k).image));
    run.frames.push_back({t, file});
  }
  // Odometry: the truth relative to the first pose, 2 % long, interpolated between frames.
  for (std::size_t k = 0; k + 1 < truth.size(); ++k) {
    for (int i = 0; i < 10; ++i) {
      const double s = i / 10.0;
      const geometry::Pose2 a = truth[0].pose.Inverse() * truth[k].pose;
      const geometry::Pose2 b = truth[0].pose.Inverse() * truth[k + 1].pose;
      const double x = 1.02 * (a.x + s * (b.x - a.x)), y = 1.02 * (a.y + s * (b.y - a.y));
      run.odometry.push_back({truth[k].t + s * (truth[k + 1].t - truth[k].t), {x, y, 0.0}});
    }
  }
  const geometry::Pose2 last = truth[0].pose.Inverse() * truth.back().pose;
  run.odometry.push_back({truth.back().t, {1.02 * last.x, 1.02 * last.y, 0.0}});
  run.truth = truth;
  run.initial_pose = truth[0].pose;
  run.initial_sigma = {0.01, 0.01, 0.01};
  EXPECT_TRUE(run_io::WriteRun(run).ok());
  return run;
}

TEST(AgentMultiFrameRelocalization, FindsThePoseFromTwoFramesWhenEachAloneIsAmbiguous) {
  const cv::Mat floor = RepeatedFloor();
  testing::MapServerFixture server("agent_multiframe_relocalization", floor, kDomain);
  const run_io::Run run = WriteDrive(server.dir() / "run", floor);

  transport::Participant& p = server.participant();
  auto index = transport::PlaceIndexReceiver::Create(p);
  ASSERT_TRUE(index.ok());
  std::vector<transport::PlaceIndexBlob> blobs;
  ASSERT_TRUE(Eventually(
      [&] {
        blobs = (*index)->Poll();
        return !blobs.empty();
      },
      30))
      << "no place index published";

  // Every frame is relocalized (no interval); two frames make a trajectory.
  const std::string config = (server.dir() / "agent.json").string();
  std::ofstream(config) << R"({"run": ")" << run.dir.string()
                        << R"(", "relocalize_interval_s": 0, "relocalize_trajectory_frames": 2})";
  auto pose_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  auto pose_reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *pose_topic, transport::Qos().Reliable().KeepAll());
  const std::string summary_path = (server.dir() / "summary.json").string();
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent",
      {"--run", run.dir.string(), "--config", config, "--relocalize", "--domain",
       std::to_string(kDomain), "--vehicle-id", "agv-6", "--outbox",
       (server.dir() / "outbox.db").string(), "--summary", summary_path},
      (server.dir() / "agent.log").string());
  std::vector<transport::PoseReport> published;
  ASSERT_TRUE(Eventually(
      [&] {
        testing::TakePoses(*pose_reader, &published);
        return !agent.Running();
      },
      90));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  testing::TakePoses(*pose_reader, &published);

  // No pose from the first frame alone; every pose published is within 2 mm and 0.5° of truth.
  EXPECT_EQ(testing::PoseAt(published, run.truth[0].t), nullptr) << "a pose from one frame";
  int localized = 0;
  for (const geometry::StampedPose& truth : run.truth) {
    const transport::PoseReport* pose = testing::PoseAt(published, truth.t);
    if (pose == nullptr) continue;
    const geometry::Pose2& found = pose->base_in_map.pose;
    EXPECT_LT(std::hypot(found.x - truth.pose.x, found.y - truth.pose.y), 0.002) << "t=" << truth.t;
    EXPECT_LT(std::abs(geometry::WrapAngle(found.theta - truth.pose.theta)), 0.5 * M_PI / 180);
    localized += pose->state == tracking::LockState::kTracking ||
                 pose->state == tracking::LockState::kRelocalized;
  }
  // Found on the second frame, from both frames, then tracked to the end.
  const transport::PoseReport* second = testing::PoseAt(published, run.truth[1].t);
  ASSERT_NE(second, nullptr) << "the second frame did not relocalize";
  EXPECT_EQ(second->state, tracking::LockState::kRelocalized);
  EXPECT_EQ(localized, static_cast<int>(run.truth.size()) - 1);

  std::ifstream in(summary_path);
  ASSERT_TRUE(in.good()) << "no summary";
  const nlohmann::json reloc = nlohmann::json::parse(in)["relocalization"];
  EXPECT_EQ(reloc.value("attempts", 0), 2) << reloc.dump();
  EXPECT_EQ(reloc.value("found", 0), 1) << reloc.dump();
  EXPECT_EQ(reloc.value("found_from_trajectory", 0), 1) << reloc.dump();
  EXPECT_EQ(reloc.value("ambiguous", 0), 1) << reloc.dump();

  // The map server found the repetition itself when it built the index: places with a twin in
  // its health, and a warning naming them.
  ASSERT_TRUE(Eventually([&] { return server.HealthCounter("self_similarity_checked") > 0; }, 60))
      << "no self-similarity check";
  EXPECT_GE(server.HealthCounter("self_similar_places"), 1u);
  EXPECT_NE(server.HealthIssue().find("self_similar_floor: "), std::string::npos)
      << server.HealthIssue();
}

}  // namespace
}  // namespace fleetloc
