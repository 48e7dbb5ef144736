// Calibration on the real OpenCV chessboard photographs: intrinsics close to OpenCV's own
// reference for this camera, and a rectified floor view in which the board is an exact square grid
// at the requested resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calibration/camera_calibration.h"
#include "calibration/rectifier.h"

namespace fleetloc::calibration {
namespace {

std::vector<cv::Mat> Views() {
  std::vector<cv::Mat> views;
  for (int i : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    char name[64];
    std::snprintf(name, sizeof name, "/tests/data/calibration/left%02d.jpg", i);
    views.push_back(cv::imread(std::string(FLEETLOC_SOURCE_DIR) + name, cv::IMREAD_GRAYSCALE));
    EXPECT_FALSE(views.back().empty()) << name;
  }
  return views;
}

TEST(Calibration, IntrinsicsMatchOpenCvsReferenceForThisCamera) {
  auto intrinsics = CalibrateIntrinsics(Views(), {});
  ASSERT_TRUE(intrinsics.ok()) << intrinsics.status().message();
  EXPECT_EQ(intrinsics->views, 13);
  EXPECT_LT(intrinsics->rms_px, 0.5);
  // OpenCV's samples/data/left_intrinsics.yml: fx = fy = 535.9, cx = 342.3, cy = 235.6.
  EXPECT_NEAR(intrinsics->K(0, 0), 535.9, 0.02 * 535.9);
  EXPECT_NEAR(intrinsics->K(1, 1), 535.9, 0.02 * 535.9);
  EXPECT_NEAR(intrinsics->K(0, 2), 342.3, 8.0);
  EXPECT_NEAR(intrinsics->K(1, 2), 235.6, 8.0);
  EXPECT_LT(intrinsics->dist[0], -0.2);  // strong barrel distortion, k1 ≈ -0.27
}

TEST(Calibration, RectifiedFloorViewIsAnExactSquareGrid) {
  const std::vector<cv::Mat> views = Views();
  const ChessboardSpec board;
  auto intrinsics = CalibrateIntrinsics(views, board);
  ASSERT_TRUE(intrinsics.ok());
  const cv::Mat& floor = views[0];  // left01: the board taken as lying on the floor
  auto H = GroundHomography(floor, *intrinsics, board);
  ASSERT_TRUE(H.ok()) << H.status().message();
  // Centre the rectified view on the board: its centre corner's camera_ground point.
  const auto corners = FindChessboard(floor, board.inner_corners);
  ASSERT_TRUE(corners.has_value());
  std::vector<cv::Point2f> undistorted;
  cv::undistortPoints(std::vector<cv::Point2f>{(*corners)[22]}, undistorted, intrinsics->K,
                      intrinsics->dist, cv::noArray(), intrinsics->K);
  const cv::Vec3d g = *H * cv::Vec3d(undistorted[0].x, undistorted[0].y, 1);
  geometry::CameraModel rectified;
  rectified.width_px = rectified.height_px = 600;
  rectified.resolution_m = 0.0005;  // 50 px per 25 mm square
  rectified.cx_px = 300 + g[1] / g[2] / rectified.resolution_m;
  rectified.cy_px = 300 + g[0] / g[2] / rectified.resolution_m;
  const Rectifier rectifier(intrinsics->K, intrinsics->dist, *H, rectified);
  const cv::Mat top = rectifier.Rectify(floor);
  const auto grid = FindChessboard(top, board.inner_corners);
  ASSERT_TRUE(grid.has_value()) << "board not found in the rectified view";
  double worst_spacing = 0, worst_angle = 0, sum_angle = 0;
  int cells = 0;
  for (int r = 0; r + 1 < board.inner_corners.height; ++r) {
    for (int c = 0; c + 1 < board.inner_corners.width; ++c) {
      const cv::Point2f p = (*grid)[r * 9 + c], right = (*grid)[r * 9 + c + 1],
                        down = (*grid)[(r + 1) * 9 + c];
      const cv::Point2f dx = right - p, dy = down - p;
      worst_spacing =
          std::max({worst_spacing, std::abs(cv::norm(dx) - 50.0), std::abs(cv::norm(dy) - 50.0)});
      const double angle_error =
          std::abs(std::acos(dx.dot(dy) / (cv::norm(dx) * cv::norm(dy))) - M_PI / 2);
      worst_angle = std::max(worst_angle, angle_error);
      sum_angle += angle_error;
      ++cells;
    }
  }
  EXPECT_LT(worst_spacing, 1.0);  // < 2 % of a square
  // Square corners: on average within 0.5° (0.4 px over a 50 px side, the corner detector's noise
  // on this oblique, upsampled view); the worst cell within 1.5°.
  EXPECT_LT(sum_angle / cells * 180 / M_PI, 0.5) << "worst " << worst_angle * 180 / M_PI;
  EXPECT_LT(worst_angle * 180 / M_PI, 1.5);
  EXPECT_NEAR(cv::norm((*grid)[22] - cv::Point2f(300, 300)), 0.0, 2.0);  // centred as asked
}

TEST(Calibration, TooFewBoardsIsBadInput) {
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  auto intrinsics = CalibrateIntrinsics({blank, blank, blank, blank}, {});
  ASSERT_FALSE(intrinsics.ok());
  EXPECT_NE(intrinsics.status().message().find("found in 0 images"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::calibration
