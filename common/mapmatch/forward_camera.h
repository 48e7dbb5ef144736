// The calibrated forward (landmark) camera: OpenCV pinhole + distortion model, mounted on the
// vehicle at a height above the floor, pitched down. Projects base_link points to pixels and
// back-projects pixels to the floor plane z = 0 (inverse perspective mapping, paper 001 §6.1).
//
// Frames: base_link is x forward, y left, z up, the floor is z = 0. The camera's optical frame
// (x right, y down, z along the optical axis) is rotated from base_link by yaw about z, then pitch
// about the (new) y axis, positive looking down, then roll about the optical axis.
#pragma once

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::mapmatch {

// Where the camera sits on the vehicle (docs/forward_camera.md, "mount").
struct ForwardMount {
  double x_m = 0.0;  // optical centre in base_link
  double y_m = 0.0;
  double height_m = 1.0;   // above the floor, > 0
  double yaw_rad = 0.0;    // optical axis heading, counter-clockwise from base_link +x
  double pitch_rad = 0.0;  // optical axis below the horizontal, in (-pi/2, pi/2)
  double roll_rad = 0.0;   // about the optical axis
};

// The content of forward_camera.json.
struct ForwardCameraParams {
  int width_px = 640;
  int height_px = 480;
  std::array<double, 9> K{500, 0, 320, 0, 500, 240, 0, 0, 1};  // row-major intrinsics
  std::array<double, 5> dist{};                                // k1, k2, p1, p2, k3 (OpenCV order)
  ForwardMount mount;
};

// One out-of-range parameter: its forward_camera.json name ("mount.height") and what is wrong.
struct ParamProblem {
  std::string field;
  std::string what;
};

// The first parameter that is not finite or out of range, or nullopt when all are valid.
std::optional<ParamProblem> FindProblem(const ForwardCameraParams& params);

class ForwardCamera {
 public:
  // InvalidInput "forward camera: field '<name>': <what>" for invalid parameters.
  static Result<ForwardCamera> Create(const ForwardCameraParams& params);

  const ForwardCameraParams& params() const { return params_; }
  cv::Size image_size() const { return {params_.width_px, params_.height_px}; }
  cv::Matx33d CameraMatrix() const;
  cv::Vec<double, 5> DistCoeffs() const;

  // The optical centre in base_link and the rotation taking optical-frame vectors to base_link.
  const Eigen::Vector3d& center() const { return center_; }
  const Eigen::Matrix3d& rotation() const { return rotation_; }

  // A base_link point → its (distorted) pixel. InvalidInput when the point is not in front of
  // the camera or far outside the field of view (its undistorted pixel beyond half the image
  // size from the image border), where the distortion polynomial is not invertible.
  Result<Eigen::Vector2d> Project(const Eigen::Vector3d& point_base) const;

  // Distorted pixels → normalized image coordinates (x/z, y/z of the optical-frame ray), by
  // OpenCV's iterative undistortion run to convergence.
  std::vector<Eigen::Vector2d> Undistort(std::span<const Eigen::Vector2d> pixels) const;
  // Undistorted ("ideal", same K without distortion) pixels ↔ normalized coordinates.
  Eigen::Vector2d IdealPixelToNormalized(const Eigen::Vector2d& ideal_px) const;
  Eigen::Vector2d NormalizedToIdealPixel(const Eigen::Vector2d& normalized) const;

  // The base_link direction of the ray through normalized coordinates (not unit length).
  Eigen::Vector3d RayDirection(const Eigen::Vector2d& normalized) const;

  // Inverse perspective mapping: the floor point (base_link x, y) seen at a distorted pixel, an
  // ideal pixel, or normalized coordinates. InvalidInput when the ray does not point below the
  // horizon.
  Result<Eigen::Vector2d> PixelToFloor(const Eigen::Vector2d& pixel) const;
  Result<Eigen::Vector2d> IdealPixelToFloor(const Eigen::Vector2d& ideal_px) const;
  Result<Eigen::Vector2d> NormalizedToFloor(const Eigen::Vector2d& normalized) const;

  // Where world-vertical lines meet in the ideal image: homogeneous ideal-pixel coordinates of
  // the downward vertical direction (third component 0 when the camera is level).
  Eigen::Vector3d NadirVanishingPoint() const;

 private:
  explicit ForwardCamera(const ForwardCameraParams& params);

  ForwardCameraParams params_;
  Eigen::Vector3d center_;
  Eigen::Matrix3d rotation_;  // optical → base_link
};

}  // namespace fleetloc::mapmatch
