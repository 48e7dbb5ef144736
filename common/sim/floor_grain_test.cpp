// Tests for the floor grain: fixed per floor point, of the configured strength, not periodic.
#include "sim/floor_grain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::sim {
namespace {

cv::Mat Grained(const FloorGrain& grain, const cv::Rect& rect) {
  cv::Mat block(rect.size(), CV_8UC1, cv::Scalar(128));
  grain.Apply(rect, &block);
  return block;
}

TEST(FloorGrain, FloorPointGetsTheSameGrainInEveryBlock) {
  const FloorGrain grain(3.0, 5);
  const cv::Rect a(-300, 100, 700, 400), b(-50, 250, 600, 500);
  const cv::Mat block_a = Grained(grain, a), block_b = Grained(grain, b);
  const cv::Rect overlap = a & b;
  EXPECT_EQ(cv::norm(block_a(overlap - a.tl()), block_b(overlap - b.tl()), cv::NORM_INF), 0.0);
  EXPECT_EQ(block_a.at<std::uint8_t>(17, 33),
            cv::saturate_cast<std::uint8_t>(128.0f + grain.At(a.x + 33, a.y + 17)));
}

TEST(FloorGrain, HasTheConfiguredStrengthAndZeroMean) {
  const FloorGrain grain(3.0, 5);
  cv::Mat values;
  Grained(grain, cv::Rect(1000, -2000, 1024, 1024)).convertTo(values, CV_64F, 1.0, -128.0);
  cv::Scalar mean, stddev;
  cv::meanStdDev(values, mean, stddev);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(stddev[0], std::sqrt(9.0 + 1.0 / 12.0), 0.1);  // grain plus rounding
}

TEST(FloorGrain, DoesNotRepeatWithTheTilePeriod) {
  const FloorGrain grain(3.0, 5);
  cv::Mat base, shifted_x, shifted_y;
  Grained(grain, cv::Rect(0, 0, 512, 512)).convertTo(base, CV_32F);
  Grained(grain, cv::Rect(256, 0, 512, 512)).convertTo(shifted_x, CV_32F);
  Grained(grain, cv::Rect(0, 256, 512, 512)).convertTo(shifted_y, CV_32F);
  cv::Mat correlation;
  cv::matchTemplate(base, shifted_x, correlation, cv::TM_CCOEFF_NORMED);
  EXPECT_LT(std::abs(correlation.at<float>(0, 0)), 0.05);
  cv::matchTemplate(base, shifted_y, correlation, cv::TM_CCOEFF_NORMED);
  EXPECT_LT(std::abs(correlation.at<float>(0, 0)), 0.05);
}

TEST(FloorGrain, ZeroStrengthLeavesTheMosaicAlone) {
  const FloorGrain grain(0.0, 5);
  EXPECT_EQ(cv::countNonZero(Grained(grain, cv::Rect(3, 4, 50, 60)) != 128), 0);
}

}  // namespace
}  // namespace fleetloc::sim
