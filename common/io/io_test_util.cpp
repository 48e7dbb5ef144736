// Test helpers for the io tests.
#include "io/io_test_util.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

namespace fleetloc::io::testing {

namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() /
          ("fleetloc_io_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

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

::testing::AssertionResult HasError(const Status& status, StatusCode code, const fs::path& file,
                                    int line, const std::string& field) {
  std::string prefix = file.string();
  if (line > 0) prefix.append(":").append(std::to_string(line));
  prefix += ": ";
  if (!field.empty()) prefix += "field '" + field + "': ";
  const std::string& message = status.message();
  if (status.code() != code) {
    return ::testing::AssertionFailure()
           << "status code " << static_cast<int>(status.code()) << ", expected "
           << static_cast<int>(code) << ": " << message;
  }
  if (message.rfind(prefix, 0) != 0) {
    return ::testing::AssertionFailure()
           << "message '" << message << "' does not start with '" << prefix << "'";
  }
  if (message.find('\n') != std::string::npos || message.size() <= prefix.size()) {
    return ::testing::AssertionFailure() << "not a one-line explanation: '" << message << "'";
  }
  return ::testing::AssertionSuccess() << message;
}

}  // namespace fleetloc::io::testing
