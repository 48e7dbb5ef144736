// Tests of the tyre marks, debris and the vehicle's shadow: coverage as configured, the same
// marks on every visit, nothing when off.
#include "sim/floor_marks.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace fleetloc::sim {
namespace {

constexpr double kPixelM = 0.0005;

// Pixel (u, v) of an image whose pixel (0, 0) corner lies at map `origin_m`, unrotated.
Eigen::Matrix<double, 2, 3> PixelToMap(const Eigen::Vector2d& origin_m) {
  Eigen::Matrix<double, 2, 3> a;
  a << kPixelM, 0, origin_m.x(), 0, kPixelM, origin_m.y();
  return a;
}

RenderOptions Marks(double tyre, double debris) {
  RenderOptions options;
  options.tyre_mark_fraction = tyre;
  options.debris_fraction = debris;
  return options;
}

double CoverageOver(const FloorMarks& marks, int size_px, cv::Mat* image) {
  *image = cv::Mat(size_px, size_px, CV_32FC1, cv::Scalar(128.0));
  return marks.Apply(PixelToMap({0.3, -0.7}), cv::Rect(0, 0, size_px, size_px), image);
}

TEST(FloorMarks, CoverTheConfiguredShareOfTheFloor) {
  cv::Mat image;
  // 1.5 m × 1.5 m of floor: some 30 tyre marks, thousands of pieces of debris.
  const double tyres = CoverageOver(FloorMarks(Marks(0.1, 0.0), kPixelM, 7), 3000, &image);
  EXPECT_GT(tyres, 0.05);
  EXPECT_LT(tyres, 0.15);
  const double debris = CoverageOver(FloorMarks(Marks(0.0, 0.05), kPixelM, 7), 3000, &image);
  EXPECT_GT(debris, 0.035);
  EXPECT_LT(debris, 0.065);
}

TEST(FloorMarks, ChangeThePixelsTheyCover) {
  cv::Mat image;
  const double covered = CoverageOver(FloorMarks(Marks(0.1, 0.05), kPixelM, 3), 2000, &image);
  const cv::Mat changed = cv::abs(image - 128.0) > 1.0;
  const double changed_share = cv::countNonZero(changed) / (2000.0 * 2000.0);
  EXPECT_GT(covered, 0.05);
  EXPECT_GE(changed_share, covered * 0.9);  // every covered pixel changed, and the soft edges too
}

TEST(FloorMarks, AreTheSameOnEveryVisit) {
  const FloorMarks marks(Marks(0.2, 0.1), kPixelM, 11);
  cv::Mat a(600, 600, CV_32FC1, cv::Scalar(100.0)), b(600, 600, CV_32FC1, cv::Scalar(100.0));
  marks.Apply(PixelToMap({0.0, 0.0}), cv::Rect(0, 0, 600, 600), &a);
  // The second view starts 200 px right and 150 px down of the first.
  marks.Apply(PixelToMap({200 * kPixelM, 150 * kPixelM}), cv::Rect(0, 0, 600, 600), &b);
  const cv::Mat overlap_a = a(cv::Rect(200, 150, 400, 450)),
                overlap_b = b(cv::Rect(0, 0, 400, 450));
  EXPECT_LT(cv::norm(overlap_a, overlap_b, cv::NORM_INF), 1e-3);
  EXPECT_GT(cv::norm(a - 100.0, cv::NORM_INF), 10.0);  // and there was something to compare
}

TEST(FloorMarks, DoNothingWhenOff) {
  cv::Mat image;
  EXPECT_EQ(CoverageOver(FloorMarks(Marks(0.0, 0.0), kPixelM, 1), 500, &image), 0.0);
  EXPECT_EQ(cv::norm(image - 128.0, cv::NORM_INF), 0.0);
}

TEST(ShadowField, DarkensTheConfiguredShareOfTheFrame) {
  const cv::Mat field = ShadowField({640, 480}, 0.3, 0.6, 0.7, 6.0);
  ASSERT_EQ(field.type(), CV_32FC1);
  double lo = 0, hi = 0;
  cv::minMaxLoc(field, &lo, &hi);
  EXPECT_NEAR(lo, 0.4, 1e-6);
  EXPECT_NEAR(hi, 1.0, 1e-6);
  const double dark_share = cv::countNonZero(field < 0.7) / (640.0 * 480.0);
  EXPECT_NEAR(dark_share, 0.3, 0.01);
  EXPECT_TRUE(ShadowField({640, 480}, 0.0, 0.6, 0.7, 6.0).empty());
}

}  // namespace
}  // namespace fleetloc::sim
