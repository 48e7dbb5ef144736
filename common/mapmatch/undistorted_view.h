// The forward camera's whole image undistorted onto a pinhole canvas with the camera's focal
// lengths. The canvas reaches past the image frame where barrel distortion pushes the periphery out
// (an undistorted image of the frame's own size would crop corners seen near the border). Canvas
// pixel = ideal pixel (K · normalized coordinates) + offset.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "mapmatch/forward_camera.h"

namespace fleetloc::mapmatch {

class UndistortedView {
 public:
  // `margin_px`: the valid mask leaves out this much along the sensor's border.
  UndistortedView(const ForwardCamera& camera, int margin_px);

  // The CV_32FC1 canvas of a CV_32FC1 image of the camera's size; beyond the sensor the border
  // pixels are replicated (see valid_mask).
  cv::Mat Undistort(const cv::Mat& image) const;

  // CV_8UC1, 255 where the canvas shows the sensor at least margin_px inside its border.
  const cv::Mat& valid_mask() const { return valid_; }
  // Canvas pixel minus ideal pixel.
  const Eigen::Vector2d& offset() const { return offset_; }

 private:
  cv::Mat map_x_, map_y_, valid_;
  Eigen::Vector2d offset_;
};

}  // namespace fleetloc::mapmatch
