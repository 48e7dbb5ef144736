// Rectification maps: rectified pixel → floor → undistorted pixel → raw pixel.
#include "calibration/rectifier.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::calibration {

Rectifier::Rectifier(const cv::Matx33d& K, const std::vector<double>& dist,
                     const cv::Matx33d& H_ground, const geometry::CameraModel& rectified) {
  const int w = rectified.width_px, h = rectified.height_px;
  const cv::Matx33d to_pixel = H_ground.inv();
  // Normalized camera rays of every rectified pixel's floor point, then lens distortion through
  // cv::projectPoints (which knows every OpenCV distortion model).
  std::vector<cv::Point3d> rays;
  rays.reserve(static_cast<size_t>(w) * h);
  const cv::Matx33d K_inv = K.inv();
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector2d ab = rectified.PixelToGround({u, v});
      const cv::Vec3d px = to_pixel * cv::Vec3d(ab.x(), ab.y(), 1.0);
      const cv::Vec3d ray = K_inv * cv::Vec3d(px[0] / px[2], px[1] / px[2], 1.0);
      rays.emplace_back(ray[0] / ray[2], ray[1] / ray[2], 1.0);
    }
  }
  std::vector<cv::Point2d> raw;
  cv::projectPoints(rays, cv::Vec3d::zeros(), cv::Vec3d::zeros(), K, dist, raw);
  cv::Mat map_x(h, w, CV_32F), map_y(h, w, CV_32F);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      map_x.at<float>(v, u) = static_cast<float>(raw[v * w + u].x);
      map_y.at<float>(v, u) = static_cast<float>(raw[v * w + u].y);
    }
  }
  cv::convertMaps(map_x, map_y, map1_, map2_, CV_16SC2);
}

cv::Mat Rectifier::Rectify(const cv::Mat& raw) const {
  cv::Mat out;
  cv::remap(raw, out, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  return out;
}

}  // namespace fleetloc::calibration
