// End-to-end tests of the tracker cycle on a real photo (tracking/test_scene.h: frames rendered
// at known poses from the formulas of docs/formats.md), drifting odometry, photometric change.
// Checks accuracy against ground truth and the lock states.
#include "tracking/mosaic_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "tracking/test_scene.h"

namespace fleetloc::tracking {
namespace {

using geometry::Pose2;

using Scene = TestScene;

Pose2 CircleBase(double s) {  // camera centre circles the middle of the floor
  const double r = 0.05, cx = 0.128, cy = 0.128;
  const Pose2 camera{cx + r * std::cos(s), cy + r * std::sin(s), s + M_PI / 2};
  return camera * Pose2{0.1, 0.0, 0.0}.Inverse();
}

// A 160×120 frame holds fewer and smaller templates than the 640×480 default.
TrackerOptions SmallFrameOptions() {
  TrackerOptions options;
  options.max_templates = 12;
  options.template_size_px = 32;
  options.coarse_template_size_px = 32;
  options.candidate_step_px = 8;
  return options;
}

// Drives `frames` frames around the circle with drifting odometry (2 % scale error and a heading
// bias, integrated from true increments); each frame's result and its true base pose.
std::vector<std::pair<FrameResult, Pose2>> DriveCircle(Scene& scene, const TrackerOptions& options,
                                                       int frames) {
  mosaic::ImageRasterSource source(scene.floor, scene.geo);
  MosaicTracker tracker(options, scene.camera, &source);
  Pose2 odom{0, 0, 0}, truth_prev = CircleBase(0);
  tracker.Reset({{truth_prev.x + 0.001, truth_prev.y - 0.001, truth_prev.theta + 0.005},
                 Eigen::Vector3d(4e-6, 4e-6, 1e-4).asDiagonal()},
                odom);
  std::vector<std::pair<FrameResult, Pose2>> results;
  for (int k = 1; k <= frames; ++k) {
    const Pose2 truth = CircleBase(0.15 * k);
    Pose2 step = geometry::Between(truth_prev, truth);
    step = {step.x * 1.02, step.y * 1.02, step.theta * 1.01 + 0.002};
    odom = odom * step;
    truth_prev = truth;
    const cv::Mat frame = scene.Render(truth, 0.8 + 0.01 * k, 10.0);
    results.emplace_back(tracker.Track(frame, 0.1 * k, odom), truth);
  }
  return results;
}

// Camera-centre RMS (px) of a drive's frames against their truth.
double CameraRmsPx(const Scene& scene, const std::vector<std::pair<FrameResult, Pose2>>& drive) {
  double sum_sq = 0;
  for (const auto& [r, truth] : drive) {
    const Pose2 est = r.base_in_map.pose * scene.camera.mount;
    const Pose2 cam = truth * scene.camera.mount;
    sum_sq += std::pow(est.x - cam.x, 2) + std::pow(est.y - cam.y, 2);
  }
  return std::sqrt(sum_sq / static_cast<double>(drive.size())) / scene.camera.resolution_m;
}

TEST(MosaicTracker, TracksRealFloorWithDriftingOdometryToSubpixelAccuracy) {
  Scene scene;
  ASSERT_FALSE(scene.floor.empty());
  TrackerOptions options = SmallFrameOptions();
  options.coarse_levels = 1;
  ASSERT_TRUE(Validate(options).ok());
  double sum_sq_theta = 0;
  const int frames = 40;
  int k = 0;
  const auto drive = DriveCircle(scene, options, frames);
  for (const auto& [r, truth] : drive) {
    ++k;
    ASSERT_EQ(r.state, LockState::kTracking) << "frame " << k;
    EXPECT_GE(r.inliers, options.min_inliers);
    const double heading_error =
        (r.base_in_map.pose * scene.camera.mount).theta - (truth * scene.camera.mount).theta;
    sum_sq_theta += std::pow(geometry::WrapAngle(heading_error), 2);
  }
  const double rms_px = CameraRmsPx(scene, drive);
  const double rms_deg = std::sqrt(sum_sq_theta / frames) * 180 / M_PI;
  std::printf("camera position RMS %.4f px, heading RMS %.4f deg\n", rms_px, rms_deg);
  EXPECT_LT(rms_px, 0.1);
  EXPECT_LT(rms_deg, 0.05);  // a 160 px frame has a short lever arm for heading
}

// The refine pass starts at a pose good to a small fraction of a pixel: re-matching in ±1 px is as
// accurate as in ±2 px (the quadratic fit reads the same 3×3 neighbourhood; a template whose peak
// is off the centre is matched again in ±2 px). Not bit-equal: NccSurface's float window sums
// slide from each window's own first column, and on these noisy 160×120 frames a template near
// the outlier threshold can fall either side (measured: 0.003-0.011 px apart a frame).
TEST(MosaicTracker, TheRefinePassInA3x3WindowIsAsAccurateAsInA5x5One) {
  Scene scene;
  ASSERT_FALSE(scene.floor.empty());
  TrackerOptions options = SmallFrameOptions();
  options.polish_max_frame_pixels = 0;  // the refine pass runs on frames that are not polished
  options.refine_pass_radius_px = 2;
  ASSERT_TRUE(Validate(options).ok());
  const auto wide = DriveCircle(scene, options, 30);
  options.refine_pass_radius_px = 1;
  const auto narrow = DriveCircle(scene, options, 30);
  for (size_t i = 0; i < wide.size(); ++i) {
    ASSERT_EQ(narrow[i].first.state, LockState::kTracking) << "frame " << i;
    const Pose2 a = narrow[i].first.base_in_map.pose * scene.camera.mount;
    const Pose2 b = wide[i].first.base_in_map.pose * scene.camera.mount;
    EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y) / scene.camera.resolution_m, 0.05) << "frame " << i;
  }
  const double narrow_rms = CameraRmsPx(scene, narrow), wide_rms = CameraRmsPx(scene, wide);
  std::printf("camera RMS: refine pass ±1 px %.4f px, ±2 px %.4f px\n", narrow_rms, wide_rms);
  EXPECT_LT(narrow_rms, 1.1 * wide_rms);
  options.refine_pass_radius_px = 3;  // wider than the fine passes' window
  EXPECT_FALSE(Validate(options).ok());
}

TEST(MosaicTracker, MosaicWithFewerPyramidLevelsThanTheCoarseSearchStillTracks) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.floor, scene.geo);  // 512² px: levels 0 and 1 only
  ASSERT_EQ(source.layout().levels, 2);
  TrackerOptions options;
  options.template_size_px = 32;
  options.coarse_template_size_px = 32;
  options.coarse_levels = 2;  // asks for level 2, which this mosaic does not have
  options.candidate_step_px = 8;
  options.max_templates = 12;
  ASSERT_TRUE(Validate(options).ok());
  MosaicTracker tracker(options, scene.camera, &source);
  const Pose2 start = CircleBase(0);
  tracker.Reset(
      {{start.x + 0.002, start.y, start.theta}, Eigen::Vector3d(4e-6, 4e-6, 1e-4).asDiagonal()},
      {0, 0, 0});
  const Pose2 next = CircleBase(0.1);
  const FrameResult r =
      tracker.Track(scene.Render(next, 1.0, 0.0), 0.1, geometry::Between(start, next));
  EXPECT_EQ(r.state, LockState::kTracking);
  const Pose2 error = geometry::Between(next, r.base_in_map.pose);
  EXPECT_LT(std::hypot(error.x, error.y), 0.25 * scene.camera.resolution_m);
}

// Counts the blocks the tracker reads from the mosaic (one per tile it normalizes).
class CountingSource : public mosaic::RasterSource {
 public:
  explicit CountingSource(mosaic::RasterSource* inner) : inner_(inner) {}
  const mosaic::MosaicLayout& layout() const override { return inner_->layout(); }
  cv::Mat ReadBlock(int level, const cv::Rect& rect) override {
    ++reads;
    return inner_->ReadBlock(level, rect);
  }
  int reads = 0;

 private:
  mosaic::RasterSource* inner_;
};

TEST(MosaicTracker, WarmUpNormalizesTheFirstFramesTilesAFewAtATimeWithoutChangingItsPose) {
  Scene scene;
  mosaic::ImageRasterSource image(scene.floor, scene.geo);
  TrackerOptions options = SmallFrameOptions();
  // The source's reads count the tiles normalized. A level-0 polish that also fits without the
  // matching's smoothing also reads the mosaic's own pixels for that view: not normalization (in
  // the agent those tiles are in the tile cache the warm-up filled), so turned off here.
  options.direct.polish_unsmoothed_max_sigma_ratio = 0;
  ASSERT_TRUE(Validate(options).ok());
  const Pose2 start = CircleBase(0), next = CircleBase(0.1);
  const geometry::PoseWithCovariance given{{start.x + 0.002, start.y, start.theta},
                                           Eigen::Vector3d(4e-6, 4e-6, 1e-4).asDiagonal()};
  const cv::Mat frame = scene.Render(next, 1.0, 0.0);
  auto first_frame = [&](MosaicTracker& tracker) {
    tracker.Reset(given, {0, 0, 0});
    return tracker.Track(frame, 0.1, geometry::Between(start, next));
  };
  CountingSource cold_source(&image), warm_source(&image);
  MosaicTracker cold(options, scene.camera, &cold_source),
      warm(options, scene.camera, &warm_source);
  int warmed = 0, steps = 0;
  for (int step; (step = warm.WarmUp(given, 2)) > 0; ++steps) {
    ASSERT_LE(step, 2);
    warmed += step;
  }
  EXPECT_GT(steps, 1);                    // a few tiles per call
  EXPECT_EQ(warm.WarmUp(given, 100), 0);  // nothing left
  EXPECT_EQ(warm_source.reads, warmed);   // one read per normalized tile
  const FrameResult cold_result = first_frame(cold);
  const FrameResult warm_result = first_frame(warm);
  // The warmed-up tracker's first frame normalizes nothing more; its pose is the cold one's.
  EXPECT_EQ(warm_source.reads, warmed);
  EXPECT_LE(cold_source.reads, warmed);  // the warm-up's box bounds the search: a superset
  EXPECT_GT(cold_source.reads, 0);
  EXPECT_EQ(warm_result.state, LockState::kTracking);
  EXPECT_EQ(warm_result.base_in_map.pose.x, cold_result.base_in_map.pose.x);
  EXPECT_EQ(warm_result.base_in_map.pose.y, cold_result.base_in_map.pose.y);
  EXPECT_EQ(warm_result.base_in_map.pose.theta, cold_result.base_in_map.pose.theta);
}

TEST(MosaicTracker, CoastsOnABlankFrameAndReportsLostWhenUncertaintyOutgrowsSearch) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.floor, scene.geo);
  TrackerOptions options;
  options.max_search_radius_px = 12;
  MosaicTracker tracker(options, scene.camera, &source);
  const Pose2 start = CircleBase(0);
  tracker.Reset({start, Eigen::Vector3d(1e-8, 1e-8, 1e-8).asDiagonal()}, {0, 0, 0});
  const cv::Mat blank(scene.camera.height_px, scene.camera.width_px, CV_8UC1, cv::Scalar(90));
  FrameResult r = tracker.Track(blank, 0.1, {0.01, 0, 0});
  EXPECT_EQ(r.state, LockState::kCoasting);
  EXPECT_EQ(r.inliers, 0);
  LockState last = r.state;
  for (int k = 2; k < 200 && last != LockState::kLost; ++k) {
    last = tracker.Track(blank, 0.1 * k, {0.01 * k, 0, 0}).state;
  }
  EXPECT_EQ(last, LockState::kLost);
}

}  // namespace
}  // namespace fleetloc::tracking
