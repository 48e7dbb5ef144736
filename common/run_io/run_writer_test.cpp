// Tests for WriteRun: exact round trips, relative frame paths, no stale or temporary files.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "run_io/run.h"
#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;
using testing::HasError;
using testing::TempDir;

void ExpectSamePoses(const std::vector<geometry::StampedPose>& a,
                     const std::vector<geometry::StampedPose>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].t, b[i].t) << i;
    EXPECT_EQ(a[i].pose.x, b[i].pose.x) << i;
    EXPECT_EQ(a[i].pose.y, b[i].pose.y) << i;
    EXPECT_EQ(a[i].pose.theta, b[i].pose.theta) << i;
  }
}

// A run with awkward numbers (not short decimals) and a raw camera block.
Run MakeAwkwardRun(const fs::path& dir) {
  run_io::Run run = testing::WriteValidRun(dir);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  for (auto* poses : {&run.odometry, &run.truth}) {
    for (geometry::StampedPose& p : *poses) p.pose = {u(rng) * 1e3, u(rng) * 1e-7, u(rng)};
  }
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    run.frames[i].t = run.truth[i].t = 1e9 + i / 3.0;
  }
  run.odometry.front().t = run.frames.front().t - 1.0 / 7.0;
  run.odometry.back().t = run.frames.back().t + 1.0 / 7.0;
  for (std::size_t i = 1; i + 1 < run.odometry.size(); ++i) {
    run.odometry[i].t = run.frames.front().t + (i - 1) / 5.0;
  }
  run.initial_pose = {u(rng), u(rng), u(rng)};
  run.initial_sigma = {1.0 / 3.0, 0.0, 1e-300};
  run.camera.raw = RawCamera{{500.5, 0, 8.1, 0, 500.25, 6.2, 0, 0, 1},
                             {0.1 / 3, -0.2 / 7, 1e-5, 2e-5, 0.0, 0.0, 0.0, 1e-9},
                             {u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), 0, 0, 1}};
  return run;
}

TEST(WriteRun, RoundTripIsExact) {
  TempDir dir;
  const run_io::Run written = MakeAwkwardRun(dir.path());
  ASSERT_TRUE(WriteRun(written).ok());
  Result<run_io::Run> read = ReadRun(dir.path());
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->vehicle_id, written.vehicle_id);
  EXPECT_EQ(read->initial_pose.x, written.initial_pose.x);
  EXPECT_EQ(read->initial_pose.y, written.initial_pose.y);
  EXPECT_EQ(read->initial_pose.theta, written.initial_pose.theta);
  EXPECT_EQ(read->initial_sigma, written.initial_sigma);
  ASSERT_TRUE(read->camera.raw.has_value());
  EXPECT_EQ(read->camera.raw->K, written.camera.raw->K);
  EXPECT_EQ(read->camera.raw->dist, written.camera.raw->dist);
  EXPECT_EQ(read->camera.raw->H_ground, written.camera.raw->H_ground);
  ASSERT_EQ(read->frames.size(), written.frames.size());
  for (std::size_t i = 0; i < written.frames.size(); ++i) {
    EXPECT_EQ(read->frames[i].t, written.frames[i].t);
    EXPECT_EQ(read->frames[i].file, written.frames[i].file);
  }
  ExpectSamePoses(read->odometry, written.odometry);
  ExpectSamePoses(read->truth, written.truth);
}

TEST(WriteRun, FramePathsAreRelativeToTheRun) {
  TempDir dir;
  testing::WriteValidRun(dir.path() / "run");
  EXPECT_EQ(testing::ReadText(dir.path() / "run" / "frames.csv"),
            "t,file\n0,img/f0.png\n0.1,img/f1.png\n0.2,img/f2.png\n");
  // The run moved elsewhere still reads: nothing absolute was written.
  fs::rename(dir.path() / "run", dir.path() / "moved");
  Result<run_io::Run> read = ReadRun(dir.path() / "moved");
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->frames[0].file, dir.path() / "moved" / "img" / "f0.png");
}

TEST(WriteRun, RewritingWithoutTruthRemovesTheOldTruth) {
  TempDir dir;
  run_io::Run run = testing::WriteValidRun(dir.path());
  ASSERT_TRUE(fs::exists(dir.path() / "truth.csv"));
  run.truth.clear();
  ASSERT_TRUE(WriteRun(run).ok());
  EXPECT_FALSE(fs::exists(dir.path() / "truth.csv"));
  Result<run_io::Run> read = ReadRun(dir.path());
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_TRUE(read->truth.empty());
}

TEST(WriteRun, LeavesNoTemporaryFiles) {
  TempDir dir;
  testing::WriteValidRun(dir.path());
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"camera.json", "frames.csv", "img", "odometry.csv",
                                             "run.json", "truth.csv"}));
}

TEST(WriteRun, RefusesNonFiniteOdometryNamingLineAndField) {
  TempDir dir;
  run_io::Run run = testing::WriteValidRun(dir.path() / "run");
  run.odometry[1].pose.y = INFINITY;
  EXPECT_TRUE(HasError(WriteRun(run), StatusCode::kInvalidInput,
                       dir.path() / "run" / "odometry.csv", 3, "y"));
  // The previously written, valid file is untouched.
  EXPECT_TRUE(ReadRun(dir.path() / "run").ok());
}

TEST(WriteRun, RefusesAnEmptyVehicleId) {
  TempDir dir;
  run_io::Run run = testing::WriteValidRun(dir.path());
  run.vehicle_id.clear();
  EXPECT_TRUE(
      HasError(WriteRun(run), StatusCode::kInvalidInput, dir.path() / "run.json", 0, "vehicle_id"));
}

}  // namespace
}  // namespace fleetloc::run_io
