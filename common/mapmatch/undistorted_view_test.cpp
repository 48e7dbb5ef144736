// The undistorted canvas holds the whole sensor: with barrel distortion it reaches past the frame,
// and every sensor pixel's ideal position lands inside it, on the valid mask.
#include "mapmatch/undistorted_view.h"

#include <gtest/gtest.h>

namespace fleetloc::mapmatch {
namespace {

TEST(UndistortedView, BarrelDistortedCornersStayOnTheCanvas) {
  ForwardCameraParams params;
  params.dist = {-0.15, 0.01, 0, 0, 0};
  const ForwardCamera camera = ForwardCamera::Create(params).value();
  const UndistortedView view(camera, 2);
  EXPECT_GT(view.offset().x(), 5.0) << "the canvas grows past the frame's left edge";
  EXPECT_GT(view.offset().y(), 5.0);
  const std::vector<Eigen::Vector2d> corners{{5, 5}, {634, 5}, {5, 474}, {634, 474}, {320, 240}};
  const std::vector<Eigen::Vector2d> normalized = camera.Undistort(corners);
  for (const Eigen::Vector2d& n : normalized) {
    const Eigen::Vector2d canvas = camera.NormalizedToIdealPixel(n) + view.offset();
    const cv::Point p(static_cast<int>(std::lround(canvas.x())),
                      static_cast<int>(std::lround(canvas.y())));
    ASSERT_TRUE(cv::Rect(cv::Point(), view.valid_mask().size()).contains(p)) << canvas.transpose();
    EXPECT_EQ(view.valid_mask().at<uchar>(p), 255) << canvas.transpose();
  }
  EXPECT_EQ(view.valid_mask().at<uchar>(0, 0), 0) << "the canvas corner is beyond the sensor";
}

TEST(UndistortedView, UndistortingMovesAPixelToItsIdealPosition) {
  ForwardCameraParams params;
  params.dist = {-0.15, 0.01, 0, 0, 0};
  const ForwardCamera camera = ForwardCamera::Create(params).value();
  const UndistortedView view(camera, 0);
  cv::Mat image(camera.image_size(), CV_32FC1, cv::Scalar(0));
  image.at<float>(60, 80) = 1000.0f;  // a bright dot at pixel (80, 60)
  const cv::Mat canvas = view.Undistort(image);
  cv::Point peak;
  cv::minMaxLoc(canvas, nullptr, nullptr, nullptr, &peak);
  const Eigen::Vector2d expected =
      camera.NormalizedToIdealPixel(camera.Undistort(std::vector<Eigen::Vector2d>{{80, 60}})[0]) +
      view.offset();
  EXPECT_LE(std::abs(peak.x - expected.x()), 1.0);
  EXPECT_LE(std::abs(peak.y - expected.y()), 1.0);
}

}  // namespace
}  // namespace fleetloc::mapmatch
