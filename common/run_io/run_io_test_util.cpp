// Test helpers for the run_io tests.
#include "run_io/run_io_test_util.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <string>

namespace fleetloc::run_io::testing {

namespace fs = std::filesystem;

void WriteGrayPng(const fs::path& path, int width, int height) {
  cv::Mat image(height, width, CV_8UC1);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) image.at<uchar>(v, u) = static_cast<uchar>(7 * u + 13 * v);
  }
  fs::create_directories(path.parent_path());
  ASSERT_TRUE(cv::imwrite(path.string(), image)) << path;
}

Run WriteValidRun(const fs::path& dir) {
  Run run;
  run.dir = dir;
  run.vehicle_id = "agv-7";
  run.camera.model.width_px = 16;
  run.camera.model.height_px = 12;
  run.camera.model.cx_px = 8.0;
  run.camera.model.cy_px = 6.0;
  run.camera.model.mount = {0.4, 0.0, 0.0};
  run.initial_pose = {1.0, 2.0, 0.5};
  run.initial_sigma = {0.01, 0.02, 0.03};
  for (int i = 0; i < 3; ++i) {
    const fs::path file = dir / "img" / (std::string("f") + std::to_string(i) + ".png");
    WriteGrayPng(file, 16, 12);
    run.frames.push_back({0.1 * i, file});
    run.truth.push_back({0.1 * i, {1.0 + 0.1 * i, 2.0, 0.5}});
  }
  for (int i = 0; i < 5; ++i) run.odometry.push_back({0.05 * i, {0.05 * i, 0.0, 0.01 * i}});
  const Status status = WriteRun(run);
  EXPECT_TRUE(status.ok()) << status.message();
  return run;
}

}  // namespace fleetloc::run_io::testing
