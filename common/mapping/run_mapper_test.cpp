// Tests for the mapping-run poses on frames of a real photo (tracking/test_scene.h) rendered at
// known poses around a circle driven a little more than once: drifting odometry is corrected by
// registration and loop closure to a small fraction of a pixel; runs whose frames cannot be
// registered, and non-finite odometry, are refused with a message.
#include "mapping/run_mapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "geometry/footprint.h"
#include "tracking/motion_model.h"
#include "tracking/test_scene.h"

namespace fleetloc::mapping {
namespace {

using geometry::Pose2;

constexpr int kFrames = 40;
constexpr int kFramesPerLap = 30;

// A 256×192 camera mounted 0.1 m ahead of base_link over the 512² photo (0.5 mm per pixel).
tracking::TestScene Scene() {
  tracking::TestScene scene;
  scene.camera.width_px = 256;
  scene.camera.height_px = 192;
  scene.camera.cx_px = 128;
  scene.camera.cy_px = 96;
  return scene;
}

// base_link whose camera circles 30 mm (60 px) around the middle of the photo.
Pose2 TrueBase(int k, const geometry::CameraModel& camera) {
  const double s = 2 * M_PI * k / kFramesPerLap;
  const Pose2 cam{0.128 + 0.03 * std::cos(s), 0.128 + 0.03 * std::sin(s),
                  geometry::WrapAngle(s + M_PI / 2)};
  return cam * camera.mount.Inverse();
}

struct SyntheticRun {
  MapperInput input;
  std::vector<cv::Mat> frames;
  std::vector<Pose2> true_cameras;
};

// Odometry with 3 % distance error and a heading bias of `heading_bias_rad` per frame.
SyntheticRun MakeRun(tracking::TestScene& scene, double heading_bias_rad = 0.01) {
  SyntheticRun run;
  run.input.camera = scene.camera;
  run.input.initial_base_in_map = TrueBase(0, scene.camera);
  Pose2 odom{0.5, -0.2, 1.0};
  for (int k = 0; k < kFrames; ++k) {
    if (k > 0) {
      const Pose2 step =
          geometry::Between(TrueBase(k - 1, scene.camera), TrueBase(k, scene.camera));
      odom = odom * Pose2{step.x * 1.03, step.y * 1.03, step.theta + heading_bias_rad};
    }
    run.input.frame_times_s.push_back(0.2 * k);
    run.input.odometry.push_back(odom);
    run.frames.push_back(scene.Render(TrueBase(k, scene.camera), 0.9 + 0.005 * k, 3.0));
    run.true_cameras.push_back(TrueBase(k, scene.camera) * scene.camera.mount);
  }
  return run;
}

FrameLoader LoaderOf(const std::vector<cv::Mat>& frames) {
  return [&frames](int k) -> Result<cv::Mat> { return frames.at(k); };
}

// A 256×192 frame holds few of the default 48 px templates once the overlap is cut: use 32 px.
MapperOptions SmallFrameOptions() {
  MapperOptions options;
  options.registration.tracker.template_size_px = 32;
  options.registration.tracker.coarse_template_size_px = 32;
  options.registration.tracker.candidate_step_px = 8;
  return options;
}

double MaxCornerErrorPx(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth,
                        const geometry::CameraModel& camera) {
  double worst = 0.0;
  for (size_t k = 0; k < truth.size(); ++k) {
    for (const Eigen::Vector2d& corner : geometry::FootprintInGround(camera)) {
      worst = std::max(worst, (estimate[k] * corner - truth[k] * corner).norm());
    }
  }
  return worst / camera.resolution_m;
}

TEST(RunMapper, RegistrationAndLoopClosureUndoDriftingOdometry) {
  tracking::TestScene scene = Scene();
  const SyntheticRun run = MakeRun(scene);
  std::vector<std::string> lines;
  const Result<MappedRun> mapped = MapRun(run.input, LoaderOf(run.frames), SmallFrameOptions(),
                                          [&lines](const std::string& l) { lines.push_back(l); });
  ASSERT_TRUE(mapped.ok()) << mapped.status().message();
  EXPECT_EQ(mapped->successive_registered, kFrames - 1);
  EXPECT_EQ(mapped->odometry_bridges, 0);
  EXPECT_GT(mapped->loop_registered, 0);
  EXPECT_EQ(mapped->loop_pruned, 0);
  EXPECT_FALSE(lines.empty());
  // Odometry alone ends tens of pixels off; the mapped poses stay within 0.05 px.
  std::vector<Pose2> dead_reckoned{run.true_cameras[0]};
  for (int k = 1; k < kFrames; ++k) {
    dead_reckoned.push_back(dead_reckoned.back() *
                            tracking::CameraIncrement(run.input.odometry[k - 1],
                                                      run.input.odometry[k], 0.2,
                                                      scene.camera.mount, {})
                                .pose);
  }
  EXPECT_GT(MaxCornerErrorPx(dead_reckoned, run.true_cameras, scene.camera), 20.0);
  EXPECT_LT(MaxCornerErrorPx(mapped->camera_in_map, run.true_cameras, scene.camera), 0.05);
}

TEST(RunMapper, OdometryBridgesFramesThatCannotRegisterAndTheLoopHoldsTheRest) {
  tracking::TestScene scene = Scene();
  // A heading bias far beyond the odometry model's noise, even with the camera's lever arm.
  SyntheticRun run = MakeRun(scene, 0.03);
  for (int k = 10; k <= 11; ++k) run.frames[k].setTo(128);  // e.g. a bright reflection
  const Result<MappedRun> mapped = MapRun(run.input, LoaderOf(run.frames), SmallFrameOptions());
  ASSERT_TRUE(mapped.ok()) << mapped.status().message();
  EXPECT_EQ(mapped->odometry_bridges, 3);  // 9 → 10, 10 → 11, 11 → 12
  EXPECT_EQ(mapped->successive_registered, kFrames - 1 - 3);
  EXPECT_GE(mapped->loop_outside_gate, 3);
  // Frames 12 on are tied back to frames 0 … 9 only by odometry across the gap (whose heading bias
  // here is far beyond its noise model, so the chain's prediction is off) and by the loop
  // closures, which agree among themselves: they must still sit within a tenth of a pixel.
  std::vector<Pose2> outside_estimate, outside_truth;
  for (int k = 0; k < kFrames; ++k) {
    if (k == 10 || k == 11) continue;
    outside_estimate.push_back(mapped->camera_in_map[k]);
    outside_truth.push_back(run.true_cameras[k]);
  }
  EXPECT_LT(MaxCornerErrorPx(outside_estimate, outside_truth, scene.camera), 0.1);
}

TEST(RunMapper, FramesWithoutTextureAreRefusedAsBadInput) {
  tracking::TestScene scene = Scene();
  SyntheticRun run = MakeRun(scene);
  for (cv::Mat& frame : run.frames) frame.setTo(128);
  const Result<MappedRun> mapped = MapRun(run.input, LoaderOf(run.frames), SmallFrameOptions());
  ASSERT_FALSE(mapped.ok());
  EXPECT_EQ(mapped.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(mapped.status().message().find("only 0 of 39 successive frame pairs registered (39 "
                                           "overlap by the odometry)"),
            std::string::npos)
      << mapped.status().message();
}

TEST(RunMapper, NonFiniteOdometryIsRefusedNamingTheFrame) {
  tracking::TestScene scene = Scene();
  SyntheticRun run = MakeRun(scene);
  run.input.odometry[7].y = std::numeric_limits<double>::quiet_NaN();
  const Result<MappedRun> mapped = MapRun(run.input, LoaderOf(run.frames), SmallFrameOptions());
  ASSERT_FALSE(mapped.ok());
  EXPECT_EQ(mapped.status().message(), "odometry at frame 7 is not finite");
}

TEST(RunMapper, UnreadableFrameStopsWithTheLoadersError) {
  tracking::TestScene scene = Scene();
  const SyntheticRun run = MakeRun(scene);
  const FrameLoader loader = [&run](int k) -> Result<cv::Mat> {
    if (k == 5) return InvalidInput("frames/000005.png: cannot decode image");
    return run.frames.at(k);
  };
  const Result<MappedRun> mapped = MapRun(run.input, loader, SmallFrameOptions());
  ASSERT_FALSE(mapped.ok());
  EXPECT_EQ(mapped.status().message(), "frames/000005.png: cannot decode image");
}

}  // namespace
}  // namespace fleetloc::mapping
