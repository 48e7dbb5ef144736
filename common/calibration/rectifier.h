// Rectification of raw camera frames into the top view the tracker expects (docs/formats.md): each
// rectified pixel's floor point goes through the inverse ground homography and the lens
// distortion to its raw pixel; the maps are computed once, each frame is one cv::remap.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/camera_model.h"

namespace fleetloc::calibration {

class Rectifier {
 public:
  // K, dist (OpenCV order) and H_ground of the raw camera; `rectified` gives the output size,
  // resolution and principal point.
  Rectifier(const cv::Matx33d& K, const std::vector<double>& dist, const cv::Matx33d& H_ground,
            const geometry::CameraModel& rectified);

  // The rectified CV_8UC1 frame (bilinear; 0 where the raw frame does not reach).
  cv::Mat Rectify(const cv::Mat& raw) const;

 private:
  cv::Mat map1_, map2_;  // fixed-point maps (cv::convertMaps) for a fast remap
};

}  // namespace fleetloc::calibration
