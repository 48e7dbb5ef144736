// Chessboard calibration with OpenCV's calib3d (findChessboardCorners, calibrateCamera).
#include "calibration/camera_calibration.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::calibration {
namespace {

std::vector<cv::Point3f> BoardPoints(const ChessboardSpec& board) {
  std::vector<cv::Point3f> points;
  for (int r = 0; r < board.inner_corners.height; ++r) {
    for (int c = 0; c < board.inner_corners.width; ++c) {
      points.emplace_back(static_cast<float>(c * board.square_m),
                          static_cast<float>(r * board.square_m), 0.0f);
    }
  }
  return points;
}

cv::Point2d Apply(const cv::Matx33d& H, cv::Point2d p) {
  const cv::Vec3d q = H * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

}  // namespace

std::optional<std::vector<cv::Point2f>> FindChessboard(const cv::Mat& gray, cv::Size inner) {
  std::vector<cv::Point2f> corners;
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (!cv::findChessboardCorners(gray, inner, corners, flags)) return std::nullopt;
  cv::cornerSubPix(gray, corners, {11, 11}, {-1, -1},
                   {cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40, 0.001});
  return corners;
}

Result<Intrinsics> CalibrateIntrinsics(const std::vector<cv::Mat>& views,
                                       const ChessboardSpec& board) {
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  cv::Size size;
  for (const cv::Mat& view : views) {
    if (size.area() == 0) size = view.size();
    if (view.size() != size) return InvalidInput("calibration images differ in size");
    if (auto corners = FindChessboard(view, board.inner_corners)) {
      image_points.push_back(std::move(*corners));
      object_points.push_back(BoardPoints(board));
    }
  }
  if (image_points.size() < 3) {
    return InvalidInput("the chessboard was found in " + std::to_string(image_points.size()) +
                        " images; calibration needs at least 3");
  }
  Intrinsics out;
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    out.rms_px = cv::calibrateCamera(object_points, image_points, size, K, dist, rvecs, tvecs);
  } catch (const cv::Exception& e) {
    return InvalidInput(std::string("calibration failed: ") + e.what());
  }
  out.K = cv::Matx33d(K);
  out.dist.assign(dist.begin<double>(), dist.end<double>());
  out.image_size = size;
  out.views = static_cast<int>(image_points.size());
  return out;
}

Result<cv::Matx33d> GroundHomography(const cv::Mat& floor_view, const Intrinsics& in,
                                     const ChessboardSpec& board) {
  const auto corners = FindChessboard(floor_view, board.inner_corners);
  if (!corners) return InvalidInput("the chessboard is not found in the floor view");
  std::vector<cv::Point2f> undistorted;
  cv::undistortPoints(*corners, undistorted, in.K, in.dist, cv::noArray(), in.K);
  std::vector<cv::Point2f> on_board;
  for (const cv::Point3f& p : BoardPoints(board)) on_board.emplace_back(p.x, p.y);
  const cv::Matx33d to_board(cv::findHomography(undistorted, on_board));
  // camera_ground axes measured on the floor: origin under the principal point, +a toward the
  // image's top, +b toward its left (Gram–Schmidt keeps b orthogonal to a, its side as measured).
  const cv::Point2d pp(in.K(0, 2), in.K(1, 2));
  const cv::Point2d origin = Apply(to_board, pp);
  cv::Point2d a = Apply(to_board, pp + cv::Point2d(0, -1)) - origin;
  a /= cv::norm(a);
  cv::Point2d b = Apply(to_board, pp + cv::Point2d(-1, 0)) - origin;
  b -= a * a.dot(b);
  b /= cv::norm(b);
  const cv::Matx33d to_ground(a.x, a.y, -a.dot(origin), b.x, b.y, -b.dot(origin), 0, 0, 1);
  return to_ground * to_board;
}

}  // namespace fleetloc::calibration
