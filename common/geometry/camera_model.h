// The rectified downward camera (docs/formats.md): image pixels ↔ camera_ground metres, and the
// camera's mount pose in base_link.
#pragma once

#include <Eigen/Core>

#include "geometry/pose2.h"

namespace fleetloc::geometry {

struct CameraModel {
  int width_px = 640;
  int height_px = 480;
  double resolution_m = 0.0005;  // metres per pixel of the rectified top view
  double cx_px = 320.0;          // principal point
  double cy_px = 240.0;
  Pose2 mount;  // camera_ground in base_link

  // Pixel (u, v) → camera_ground (a, b): a = -(v - cy)·res, b = -(u - cx)·res.
  Eigen::Vector2d PixelToGround(const Eigen::Vector2d& uv) const {
    return {-(uv.y() - cy_px) * resolution_m, -(uv.x() - cx_px) * resolution_m};
  }
  Eigen::Vector2d GroundToPixel(const Eigen::Vector2d& ab) const {
    return {cx_px - ab.y() / resolution_m, cy_px - ab.x() / resolution_m};
  }
};

// A pose with its time of validity (seconds).
struct StampedPose {
  double t = 0.0;
  Pose2 pose;
};

}  // namespace fleetloc::geometry
