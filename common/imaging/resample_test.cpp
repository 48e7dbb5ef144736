// Tests of the affine resampling kernels (resample.h) against OpenCV and double-precision
// references.
#include "imaging/resample.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {
namespace {

cv::Mat Gravel() {
  return cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
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
  // Both take the vectorized path (on AVX2 machines), gathering floats or bytes.
  const cv::Mat src = Gravel()(cv::Rect(50, 50, 120, 120)).clone();
  cv::Mat src_f;
  src.convertTo(src_f, CV_32F);
  const double c = std::cos(-1.1), s = std::sin(-1.1);
  const cv::Matx23d m(c, -s, 60.2, s, c, 70.9);
  EXPECT_LT(
      cv::norm(ResampleAffine(src, m, {53, 41}), ResampleAffine(src_f, m, {53, 41}), cv::NORM_INF),
      1e-3);
}

TEST(ResampleAffine, FloatSourceEqualsByteSourceAcrossTheSourcesEdgeAtEveryRowWidth) {
  // Rows whose samples leave the source part-way (zeros there) and widths that are not a multiple
  // of the vector path's 8 lanes: the float path's gathers against the byte path's, the row's
  // tail under a mask.
  const cv::Mat src = Gravel()(cv::Rect(50, 50, 40, 30)).clone();
  cv::Mat src_f;
  src.convertTo(src_f, CV_32F);
  const double c = std::cos(0.4), s = std::sin(0.4);
  for (const int width : {1, 5, 8, 9, 15, 16, 17, 31, 50}) {
    const cv::Matx23d m(c, -s, 20.3 - 0.5 * width * c, s, c, 3.7 - 0.5 * width * s);
    const cv::Mat fast = ResampleAffine(src_f, m, {width, 40});
    const cv::Mat bytes = ResampleAffine(src, m, {width, 40});
    EXPECT_LT(cv::norm(fast, bytes, cv::NORM_INF), 1e-3) << width;
    EXPECT_EQ(cv::countNonZero(fast == 0.0f), cv::countNonZero(bytes == 0.0f)) << width;
  }
}

// Bilinear src at (x, y) in double, for sources sampled wholly inside.
double ReferenceBilinear(const cv::Mat& src, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double ax = x - x0, ay = y - y0;
  const auto at = [&](int yy, int xx) { return static_cast<double>(src.at<uchar>(yy, xx)); };
  const double top = at(y0, x0) + ax * (at(y0, x0 + 1) - at(y0, x0));
  const double bottom = at(y0 + 1, x0) + ax * (at(y0 + 1, x0 + 1) - at(y0 + 1, x0));
  return top + ay * (bottom - top);
}

TEST(ResampleAffine, ByteSourceMatchesBilinearFromTheFirstPixelsToTheLastAtEveryRowWidth) {
  // 8-bit sources are gathered as 32-bit words from two bytes before each sample (the AVX2 path);
  // rows that start in the first row's first two columns fall back to the scalar path. Samples
  // from (0.3, 0.2) to the far corner's pixel, in a view of a larger image (rows strided) and in
  // a continuous copy, at widths around the vector path's 8 lanes.
  const cv::Mat parent = Gravel()(cv::Rect(50, 50, 60, 50)).clone();
  const cv::Mat view = parent(cv::Rect(0, 0, 41, 33));
  for (const cv::Mat& src : {view, view.clone()}) {
    for (const int width : {1, 7, 8, 9, 16, 17, 23}) {
      const int height = 12;
      const double s = 0.05, c = std::sqrt(1.0 - s * s);
      const double scale = 37.0 / width;  // the row spans ~37 px of the source
      const cv::Matx23d m(c * scale, s * 2.0, 0.3, s * scale, c * 2.0, 0.2);
      const cv::Mat out = ResampleAffine(src, m, {width, height});
      double worst = 0.0;
      for (int i = 0; i < height; ++i) {
        for (int j = 0; j < width; ++j) {
          const double x = m(0, 0) * j + m(0, 1) * i + m(0, 2);
          const double y = m(1, 0) * j + m(1, 1) * i + m(1, 2);
          ASSERT_TRUE(x >= 0.0 && y >= 0.0 && x < src.cols - 1 && y < src.rows - 1);
          worst = std::max(worst, std::abs(out.at<float>(i, j) - ReferenceBilinear(src, x, y)));
        }
      }
      EXPECT_LT(worst, 1e-3) << width << (src.isContinuous() ? " continuous" : " strided");
    }
  }
}

TEST(BoxAverage, EqualsOpenCvsBoxFilterForSquaresOfTwoAndFour) {
  const cv::Mat src = Gravel()(cv::Rect(30, 40, 57, 33));
  for (const int k : {1, 2, 4}) {
    cv::Mat reference;
    cv::boxFilter(src, reference, CV_32F, {k, k}, {0, 0}, true, cv::BORDER_REPLICATE);
    const cv::Mat mean = BoxAverage(src, k);
    ASSERT_EQ(mean.size(), cv::Size(src.cols - k + 1, src.rows - k + 1)) << k;
    EXPECT_LT(cv::norm(mean, reference(cv::Rect({0, 0}, mean.size())), cv::NORM_INF), 1e-4) << k;
  }
}

TEST(ResamplePairMeans, EqualsResamplingTheMaterializedMeansEverywhereAtEveryRowWidth) {
  // Exactly the same floats (the means are sums of bytes times 1/4, exact in any order): the
  // vectorized path (three rows of words from one byte before each sample), its masked tails, the
  // first row's scalar fallback (samples in the first column of the first row) and the zeros
  // where a row leaves the means' image, in a strided view and a continuous copy.
  const cv::Mat parent = Gravel()(cv::Rect(50, 50, 70, 60)).clone();
  const cv::Mat view = parent(cv::Rect(0, 0, 45, 37));
  for (const cv::Mat& src : {view, view.clone()}) {
    const cv::Mat means = BoxAverage(src, 2);
    for (const int width : {1, 7, 8, 9, 16, 17, 29}) {
      for (const double turn : {0.0, 0.4, -2.0}) {
        const double c = std::cos(turn), s = std::sin(turn);
        // From (0.2, 0.1) into the means across the row (and beyond it at the wider widths).
        const double scale = 50.0 / width;
        const cv::Matx23d m(c * scale, s, 0.2 + (turn < 0 ? 43.0 : 0.0), s * scale * 0.3,
                            c * 2.0 + 0.5, 0.1 + (turn < 0 ? 30.0 : 0.0));
        const cv::Mat fast = ResamplePairMeans(src, m, {width, 15});
        const cv::Mat reference = ResampleAffine(means, m, {width, 15});
        EXPECT_EQ(cv::norm(fast, reference, cv::NORM_INF), 0.0)
            << width << " turn " << turn << (src.isContinuous() ? " continuous" : " strided");
        EXPECT_GT(cv::countNonZero(fast), 0) << width << " turn " << turn;
      }
    }
  }
}

}  // namespace
}  // namespace fleetloc::imaging
