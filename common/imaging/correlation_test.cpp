// Tests for NCC matching: sub-pixel shifts on a real photo, peak quality on ambiguous and flat
// input, and the quadratic peak refinement on an exact quadratic.
#include "imaging/correlation.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/normalize.h"

namespace fleetloc::imaging {
namespace {

cv::Mat Shifted(const cv::Mat& image, double dx, double dy) {
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, dy);
  cv::Mat out;
  cv::warpAffine(image, out, m, image.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return out;
}

TEST(RefinePeak, RecoversTheMaximumOfAQuadratic) {
  cv::Mat s(5, 5, CV_32F);
  const double x0 = 2.3, y0 = 1.8;
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x)
      s.at<float>(y, x) = static_cast<float>(
          1.0 - 0.2 * (x - x0) * (x - x0) - 0.1 * (y - y0) * (y - y0) + 0.05 * (x - x0) * (y - y0));
  const SubpixelPeak p = RefinePeak(s, {2, 2});
  EXPECT_NEAR(2 + p.offset.x(), x0, 1e-4);
  EXPECT_NEAR(2 + p.offset.y(), y0, 1e-4);
  EXPECT_GT(p.curvature, 0.1);
}

TEST(MatchTemplate, FindsSubpixelShiftOfRealTexture) {
  cv::Mat gravel = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(gravel.empty());
  cv::GaussianBlur(gravel, gravel, {0, 0}, 0.8);  // a camera's optics
  const cv::Rect tpl_rect(200, 180, 32, 32);
  const int r = 8;
  const cv::Rect window_rect = tpl_rect + cv::Point(-r, -r) + cv::Size(2 * r, 2 * r);
  double worst = 0;
  for (const auto& [dx, dy] : {std::pair{0.0, 0.0}, {0.25, -0.4}, {-3.5, 1.2}, {5.1, 6.7}}) {
    const cv::Mat moved = Shifted(gravel, dx, dy);
    // Normalize before cropping so both crops see the same neighbourhoods.
    const Match m = MatchTemplate(LocalNormalize(moved, 9)(window_rect),
                                  LocalNormalize(gravel, 9)(tpl_rect).clone());
    ASSERT_TRUE(m.found);
    EXPECT_GT(m.peak, 0.9);
    EXPECT_LT(m.second_peak, 0.6);
    const double error = (m.offset_px - Eigen::Vector2d(r + dx, r + dy)).norm();
    std::printf("shift %.2f,%.2f error %.4f px\n", dx, dy, error);
    worst = std::max(worst, error);
  }
  EXPECT_LT(worst, 0.05);  // one pass: the quadratic fit's pixel-locking bias is a few 0.01 px
}

TEST(MatchTemplate, StripesAreAmbiguous) {
  cv::Mat stripes(64, 64, CV_32F);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) stripes.at<float>(y, x) = std::sin(0.8 * x + 0.1 * y);
  const Match m = MatchTemplate(stripes, stripes(cv::Rect(16, 16, 24, 24)).clone());
  EXPECT_GT(m.second_peak, 0.9 * m.peak);  // many equally good positions
}

TEST(MatchTemplate, PeakOnWindowBorderIsNotFound) {
  cv::Mat gravel = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  cv::Mat f;
  gravel.convertTo(f, CV_32F);
  // The template's true position is the window's corner: no interior maximum exists.
  const Match m =
      MatchTemplate(f(cv::Rect(100, 100, 48, 48)), f(cv::Rect(100, 100, 32, 32)).clone());
  EXPECT_FALSE(m.found);
}

}  // namespace
}  // namespace fleetloc::imaging
