// FramePyramid: each level the last halved by area averaging, computed once.
#include "tracking/frame_pyramid.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace fleetloc::tracking {
namespace {

TEST(FramePyramid, EachLevelIsTheLastHalvedByAreaAveraging) {
  cv::Mat frame(101, 160, CV_8UC1);
  cv::randu(frame, 0, 256);
  FramePyramid pyramid(frame);
  const cv::Mat level2 = pyramid.Level(2);
  cv::Mat half, quarter;
  cv::resize(frame, half, {80, 50}, 0, 0, cv::INTER_AREA);
  cv::resize(half, quarter, {40, 25}, 0, 0, cv::INTER_AREA);
  ASSERT_EQ(level2.size(), quarter.size());
  EXPECT_EQ(cv::norm(level2, quarter, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(pyramid.Level(1), half, cv::NORM_INF), 0.0);
  EXPECT_EQ(pyramid.Level(0).data, frame.data);
}

TEST(FramePyramid, ALevelIsComputedOnce) {
  cv::Mat frame(64, 64, CV_8UC1, cv::Scalar(7));
  FramePyramid pyramid(frame);
  const uchar* first = pyramid.Level(1).data;
  pyramid.Level(3);
  EXPECT_EQ(pyramid.Level(1).data, first);
  EXPECT_EQ(pyramid.frame().data, frame.data);
}

}  // namespace
}  // namespace fleetloc::tracking
