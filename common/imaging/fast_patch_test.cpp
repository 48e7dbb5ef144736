// The hand-written patch kernels agree with the OpenCV functions they stand in for.
#include "imaging/fast_patch.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/normalize.h"
#include "imaging/texture.h"

namespace fleetloc::imaging {
namespace {

cv::Mat Gravel() {
  return cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
}

TEST(NormalizePatch, MatchesOpenCvNormalizationAwayFromTheBorder) {
  const cv::Mat patch = Gravel()(cv::Rect(100, 120, 60, 50));
  const cv::Mat fast = NormalizePatch(patch, 11);
  const cv::Mat reference = LocalNormalize(patch, 11);
  const cv::Rect interior(5, 5, 50, 40);
  EXPECT_LT(cv::norm(fast(interior), reference(interior), cv::NORM_INF), 1e-3);
}

TEST(NormalizePatch, GivesTheLocalVarianceOfOpenCvsBoxFilterAwayFromTheBorder) {
  const cv::Mat patch = Gravel()(cv::Rect(100, 120, 60, 50));
  cv::Mat variance;
  const cv::Mat normalized = NormalizePatch(patch, 11, 2.0f, &variance);
  EXPECT_LT(cv::norm(normalized, NormalizePatch(patch, 11), cv::NORM_INF), 1e-6);
  cv::Mat f, mean, mean_sq;
  patch.convertTo(f, CV_32F);
  cv::boxFilter(f, mean, CV_32F, {11, 11});
  cv::boxFilter(f.mul(f), mean_sq, CV_32F, {11, 11});
  const cv::Mat reference = mean_sq - mean.mul(mean);
  const cv::Rect interior(5, 5, 50, 40);
  ASSERT_GT(cv::mean(reference(interior))[0], 10.0);  // a textured patch
  EXPECT_LT(cv::norm(variance(interior), reference(interior), cv::NORM_INF), 0.05);
}

TEST(ResampleAffine, MatchesWarpAffineBilinear) {
  const cv::Mat src = Gravel()(cv::Rect(50, 50, 120, 120)).clone();
  const double c = std::cos(0.3), s = std::sin(0.3);
  const cv::Matx23d m(c, -s, 40.3, s, c, 20.7);
  const cv::Mat fast = ResampleAffine(src, m, {48, 48});
  cv::Mat reference;
  cv::warpAffine(src, reference, m, {48, 48}, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP);
  reference.convertTo(reference, CV_32F);
  // OpenCV interpolates with 5-bit fixed-point weights and rounds to 8 bits.
  EXPECT_LT(cv::norm(fast, reference, cv::NORM_INF), 2.0);
  EXPECT_LT(cv::norm(fast, reference, cv::NORM_L1) / fast.total(), 0.6);
}

TEST(ResampleAffine, FloatSourceEqualsByteSourceOnTheSameImage) {
  // Float sources take the vectorized path (on AVX2 machines); both must agree to rounding.
  const cv::Mat src = Gravel()(cv::Rect(50, 50, 120, 120)).clone();
  cv::Mat src_f;
  src.convertTo(src_f, CV_32F);
  const double c = std::cos(-1.1), s = std::sin(-1.1);
  const cv::Matx23d m(c, -s, 60.2, s, c, 70.9);
  EXPECT_LT(
      cv::norm(ResampleAffine(src, m, {53, 41}), ResampleAffine(src_f, m, {53, 41}), cv::NORM_INF),
      1e-3);
}

TEST(NccSurface, MatchesMatchTemplateCoeffNormed) {
  cv::Mat f;
  Gravel().convertTo(f, CV_32F);
  const cv::Mat window = f(cv::Rect(200, 200, 44, 40)).clone();
  const cv::Mat templ = f(cv::Rect(205, 203, 32, 32)).clone();
  cv::Mat reference;
  cv::matchTemplate(window, templ, reference, cv::TM_CCOEFF_NORMED);
  const cv::Mat fast = NccSurface(window, templ);
  ASSERT_EQ(fast.size(), reference.size());
  EXPECT_LT(cv::norm(fast, reference, cv::NORM_INF), 1e-4);
  double best;
  cv::Point at;
  cv::minMaxLoc(fast, nullptr, &best, nullptr, &at);
  EXPECT_EQ(at, cv::Point(5, 3));
  EXPECT_NEAR(best, 1.0, 1e-5);
}

TEST(TextureScoreGrid, AgreesWithTheDenseScoreInRankAndScale) {
  const cv::Mat gray = Gravel();
  const cv::Mat grid = TextureScoreGrid(gray, 8, 5);
  const cv::Mat dense = TextureScore(gray, 5);
  // Central differences versus Sobel: same structure, similar magnitude at each grid point.
  double dot = 0, nd = 0, ng = 0;
  for (int r = 1; r < grid.rows - 1; ++r) {
    for (int c = 1; c < grid.cols - 1; ++c) {
      const double g = grid.at<float>(r, c), d = dense.at<float>((r + 1) * 8, (c + 1) * 8);
      dot += g * d;
      nd += d * d;
      ng += g * g;
    }
  }
  EXPECT_GT(dot / std::sqrt(nd * ng), 0.9);  // strongly correlated
  EXPECT_GT(std::sqrt(ng / nd), 0.5);
  EXPECT_LT(std::sqrt(ng / nd), 2.0);
}

}  // namespace
}  // namespace fleetloc::imaging
