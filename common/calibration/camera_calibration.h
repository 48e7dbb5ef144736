// Calibration of a raw downward camera from chessboard photographs (docs/formats.md `raw` block):
// intrinsics and distortion from several views, and the ground homography (undistorted pixels →
// camera_ground metres) from one view of the board lying on the floor.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "base/status.h"

namespace fleetloc::calibration {

struct ChessboardSpec {
  cv::Size inner_corners{9, 6};  // corners per row, per column
  double square_m = 0.025;
};

struct Intrinsics {
  cv::Matx33d K;
  std::vector<double> dist;  // k1, k2, p1, p2, k3
  cv::Size image_size;
  double rms_px = 0;  // reprojection RMS over every corner of every used view
  int views = 0;
};

// The board's inner corners, refined to sub-pixel, row by row; nullopt if the board is not found.
std::optional<std::vector<cv::Point2f>> FindChessboard(const cv::Mat& gray, cv::Size inner_corners);

// InvalidInput if fewer than 3 views show the board or the images differ in size.
Result<Intrinsics> CalibrateIntrinsics(const std::vector<cv::Mat>& gray_views,
                                       const ChessboardSpec& board);

// H with camera_ground (a, b, 1) ~ H · (undistorted u, v, 1): the board's plane is the floor, the
// origin is the floor point under the principal point, +a toward the top of the image and +b
// toward its left (docs/formats.md). InvalidInput if the board is not found in `floor_view`.
Result<cv::Matx33d> GroundHomography(const cv::Mat& floor_view, const Intrinsics& intrinsics,
                                     const ChessboardSpec& board);

}  // namespace fleetloc::calibration
