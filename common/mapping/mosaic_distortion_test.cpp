// Tests for the distortion measurement on a real photo (tests/data/gravel.png): a copy with a
// known small scale, rotation and shift is measured back to a fraction of its values; an
// undistorted copy with different gain and blur shows no displacement; unmapped areas are skipped.
#include "mapping/mosaic_distortion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::mapping {
namespace {

cv::Mat Photo() {
  return cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
}

// built(p) = truth(s·R·(p − c) + c + t): R turns by `map_rotation_rad` counter-clockwise in map,
// i.e. by −map_rotation_rad in image axes (v down).
cv::Mat Distorted(const cv::Mat& truth, double scale, double map_rotation_rad, cv::Point2d shift) {
  const double th = -map_rotation_rad, c = std::cos(th) * scale, s = std::sin(th) * scale;
  const cv::Point2d centre(truth.cols / 2.0, truth.rows / 2.0);
  const cv::Matx23d m(c, -s, centre.x + shift.x - c * centre.x + s * centre.y,  //
                      s, c, centre.y + shift.y - s * centre.x - c * centre.y);
  cv::Mat built;
  cv::warpAffine(truth, built, m, truth.size(), cv::INTER_CUBIC | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REFLECT);
  return built;
}

TEST(MosaicDistortion, KnownScaleRotationAndShiftAreMeasured) {
  const cv::Mat truth = Photo();
  ASSERT_FALSE(truth.empty());
  const cv::Mat built = Distorted(truth, 1.003, 0.002, {0.4, -0.25});
  const Result<DistortionReport> r = MeasureDistortion(built, truth);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_GE(r->patches.size(), 16u);
  EXPECT_NEAR(r->scale_error, 0.003, 2e-4);
  EXPECT_NEAR(r->rotation_rad, 0.002, 2e-4);
  EXPECT_LT(r->residual_rms_px, 0.05);
  // Displacements reach 0.003 · 256 · √2 ≈ 1.1 px plus the shift at the corners.
  EXPECT_GT(r->max_px, 0.8);
}

TEST(MosaicDistortion, UndistortedCopyWithOtherGainAndBlurHasNoDisplacement) {
  const cv::Mat truth = Photo();
  cv::Mat built;
  cv::GaussianBlur(truth, built, {0, 0}, 0.8);
  built.convertTo(built, CV_8U, 0.8, 20.0);
  const Result<DistortionReport> r = MeasureDistortion(built, truth);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_LT(r->rms_px, 0.03);
  EXPECT_LT(std::abs(r->scale_error), 1e-4);
}

TEST(MosaicDistortion, UnmappedPatchesAreSkippedAndTooFewMatchesRefused) {
  const cv::Mat truth = Photo();
  cv::Mat built = truth.clone();
  built.setTo(1, built == 0);  // 0 marks unmapped pixels only
  const Result<DistortionReport> whole = MeasureDistortion(built, truth);
  ASSERT_TRUE(whole.ok());
  built(cv::Rect(0, 0, 256, 512)).setTo(0);  // left half unmapped
  const Result<DistortionReport> half = MeasureDistortion(built, truth);
  ASSERT_TRUE(half.ok());
  EXPECT_LT(half->patches_tried, whole->patches_tried * 0.6);
  built.setTo(0);
  EXPECT_EQ(MeasureDistortion(built, truth).status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace fleetloc::mapping
