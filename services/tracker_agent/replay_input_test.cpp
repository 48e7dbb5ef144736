// ReplayInput over a run with a forward camera: odometry, frames and forward images come out
// merged by time (odometry first on equal times, then the frame, then the forward image), and an
// unreadable forward image is an error naming it after which the replay goes on.
#include "tracker_agent/replay_input.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "run_io/forward_camera_json.h"
#include "run_io/run_tables.h"

namespace fleetloc::tracker_agent {
namespace {

namespace fs = std::filesystem;
using Kind = InputEvent::Kind;

// Frames at t = 0, 0.2; odometry at 0, 0.1, 0.2; forward images at 0.1 and 0.2, the second one
// not a PNG.
run_io::Run WriteRunWithForwardImages(const fs::path& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir / "forward");
  run_io::Run run;
  run.dir = dir;
  run.vehicle_id = "agv-2";
  run.camera.model.width_px = 16;
  run.camera.model.height_px = 12;
  run.camera.model.cx_px = 8;
  run.camera.model.cy_px = 6;
  for (int i = 0; i < 2; ++i) {
    const fs::path file = dir / ("f" + std::to_string(i) + ".png");
    EXPECT_TRUE(cv::imwrite(file.string(), cv::Mat(12, 16, CV_8UC1, cv::Scalar(i))));
    run.frames.push_back({0.2 * i, file});
  }
  for (int i = 0; i < 3; ++i) run.odometry.push_back({0.1 * i, {0.1 * i, 0, 0}});
  EXPECT_TRUE(run_io::WriteRun(run).ok());
  EXPECT_TRUE(run_io::WriteForwardCameraJson(dir / "forward" / "forward_camera.json", {}).ok());
  EXPECT_TRUE(cv::imwrite((dir / "forward" / "a.png").string(), cv::Mat(480, 640, CV_8UC1)));
  std::ofstream(dir / "forward" / "b.png") << "not an image";
  EXPECT_TRUE(
      run_io::WriteFramesCsv(dir / "forward" / "forward.csv",
                             {{0.1, dir / "forward" / "a.png"}, {0.2, dir / "forward" / "b.png"}},
                             dir / "forward")
          .ok());
  Result<run_io::Run> read = run_io::ReadRun(dir);
  EXPECT_TRUE(read.ok()) << read.status().message();
  return std::move(read).value();
}

TEST(ReplayInput, MergesForwardImagesByTimeAndGoesOnAfterAnUnreadableOne) {
  const fs::path dir = fs::temp_directory_path() / ("replay_input_" + std::to_string(::getpid()));
  ReplayInput input(WriteRunWithForwardImages(dir), /*paced=*/false);
  const std::vector<std::pair<Kind, double>> expected = {
      {Kind::kOdometry, 0.0},     {Kind::kFrame, 0.0},    {Kind::kOdometry, 0.1},
      {Kind::kForwardFrame, 0.1}, {Kind::kOdometry, 0.2}, {Kind::kFrame, 0.2}};
  for (const auto& [kind, t] : expected) {
    Result<std::optional<InputEvent>> event = input.Next();
    ASSERT_TRUE(event.ok()) << event.status().message();
    ASSERT_TRUE(event->has_value());
    EXPECT_EQ((*event)->kind, kind) << "t=" << t;
    EXPECT_NEAR((*event)->t, t, 1e-12);
    if (kind == Kind::kForwardFrame) {
      EXPECT_EQ((*event)->frame.size(), cv::Size(640, 480));
    }
  }
  Result<std::optional<InputEvent>> bad = input.Next();
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("forward camera:"), std::string::npos);
  EXPECT_NE(bad.status().message().find("b.png"), std::string::npos) << bad.status().message();
  Result<std::optional<InputEvent>> end = input.Next();
  ASSERT_TRUE(end.ok());
  EXPECT_FALSE(end->has_value());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
