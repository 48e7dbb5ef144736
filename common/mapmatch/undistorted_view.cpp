// Undistortion onto a canvas that holds the whole sensor (see undistorted_view.h).
#include "mapmatch/undistorted_view.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::mapmatch {
namespace {

// The canvas may grow by at most this fraction of the image on each side (strong distortion
// would otherwise make it huge for little gain).
constexpr double kMaxGrowth = 0.5;

// The ideal-pixel bounding box of the sensor's border, sampled every few pixels.
cv::Rect2d IdealBounds(const ForwardCamera& camera) {
  const cv::Size size = camera.image_size();
  std::vector<Eigen::Vector2d> border;
  for (int u = 0; u < size.width; u += 4) {
    border.emplace_back(u, 0);
    border.emplace_back(u, size.height - 1);
  }
  for (int v = 0; v < size.height; v += 4) {
    border.emplace_back(0, v);
    border.emplace_back(size.width - 1, v);
  }
  double x0 = 0, y0 = 0, x1 = size.width - 1, y1 = size.height - 1;
  for (const Eigen::Vector2d& n : camera.Undistort(border)) {
    const Eigen::Vector2d p = camera.NormalizedToIdealPixel(n);
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
  x0 = std::max(x0, -kMaxGrowth * size.width);
  y0 = std::max(y0, -kMaxGrowth * size.height);
  x1 = std::min(x1, (1 + kMaxGrowth) * size.width);
  y1 = std::min(y1, (1 + kMaxGrowth) * size.height);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

UndistortedView::UndistortedView(const ForwardCamera& camera, int margin_px) {
  const cv::Rect2d bounds = IdealBounds(camera);
  offset_ = {-std::floor(bounds.x), -std::floor(bounds.y)};
  const cv::Size canvas(static_cast<int>(std::ceil(bounds.br().x + offset_.x())) + 1,
                        static_cast<int>(std::ceil(bounds.br().y + offset_.y())) + 1);
  cv::Matx33d canvas_K = camera.CameraMatrix();
  canvas_K(0, 2) += offset_.x();
  canvas_K(1, 2) += offset_.y();
  cv::initUndistortRectifyMap(camera.CameraMatrix(), camera.DistCoeffs(), cv::noArray(), canvas_K,
                              canvas, CV_32FC1, map_x_, map_y_);
  const cv::Mat sensor(camera.image_size(), CV_8UC1, cv::Scalar(255));
  cv::remap(sensor, valid_, map_x_, map_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  if (margin_px > 0) {
    cv::erode(valid_, valid_, cv::Mat(), cv::Point(-1, -1), margin_px, cv::BORDER_CONSTANT, 0);
  }
}

cv::Mat UndistortedView::Undistort(const cv::Mat& image) const {
  cv::Mat canvas;
  cv::remap(image, canvas, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return canvas;
}

}  // namespace fleetloc::mapmatch
