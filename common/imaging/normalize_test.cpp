// Tests for local normalization: zero mean, unit deviation, gain and bias invariance.
#include "imaging/normalize.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace fleetloc::imaging {
namespace {

TEST(LocalNormalize, RemovesGainAndBias) {
  const cv::Mat gravel =
      cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(gravel.empty());
  cv::Mat darker;
  gravel.convertTo(darker, CV_32F, 0.6, 20.0);  // gain 0.6, bias +20 grey levels
  const cv::Mat a = LocalNormalize(gravel, 15, 0.0f);
  const cv::Mat b = LocalNormalize(darker, 15, 0.0f);
  const cv::Rect interior(20, 20, gravel.cols - 40, gravel.rows - 40);
  EXPECT_LT(cv::norm(a(interior), b(interior), cv::NORM_INF), 1e-3);
  cv::Scalar mean, stddev;
  cv::meanStdDev(a(interior), mean, stddev);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(stddev[0], 0.95, 0.1);  // local windows: slightly under 1 overall
}

TEST(LocalNormalize, FlatImageStaysFinite) {
  const cv::Mat flat(32, 32, CV_8UC1, cv::Scalar(77));
  const cv::Mat n = LocalNormalize(flat, 7);
  EXPECT_TRUE(cv::checkRange(n));
  EXPECT_LT(cv::norm(n, cv::NORM_INF), 1e-4);
}

}  // namespace
}  // namespace fleetloc::imaging
