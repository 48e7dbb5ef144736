// SE(2) poses: composition (⊕), inverse, Jacobians and covariance propagation (docs/formats.md).
#pragma once

#include <Eigen/Core>

namespace fleetloc::geometry {

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle_rad);

// A rigid transform of the plane: rotation theta then translation (x, y).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  // this ⊕ other: other expressed in this pose's frame, returned in the parent frame.
  Pose2 operator*(const Pose2& other) const;
  Pose2 Inverse() const;
  // Applies the transform to a point.
  Eigen::Vector2d operator*(const Eigen::Vector2d& point) const;
  Eigen::Vector3d ToVector() const { return {x, y, theta}; }
  static Pose2 FromVector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
};

// a − b in map coordinates (x, y, wrapped theta): the error vector of a against b that the
// covariances (x, y, theta in the parent frame) describe.
Eigen::Vector3d Difference(const Pose2& a, const Pose2& b);

// a⁻¹ ⊕ b: the increment that takes a to b.
Pose2 Between(const Pose2& a, const Pose2& b);

// Jacobians of c = a ⊕ b with respect to a and to b (3×3, order x, y, theta).
Eigen::Matrix3d ComposeJacobianA(const Pose2& a, const Pose2& b);
Eigen::Matrix3d ComposeJacobianB(const Pose2& a);

// Jacobian of p' = pose * p with respect to the pose (2×3).
Eigen::Matrix<double, 2, 3> PointJacobian(const Pose2& pose, const Eigen::Vector2d& point);

// A pose with its 3×3 covariance (x, y, theta).
struct PoseWithCovariance {
  Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// (a, Σa) ⊕ (b, Σb) with first-order propagation, a and b independent.
PoseWithCovariance Compose(const PoseWithCovariance& a, const PoseWithCovariance& b);

// Moves a pose's covariance to the pose composed with a fixed offset: pose ⊕ offset.
PoseWithCovariance ComposeFixed(const PoseWithCovariance& a, const Pose2& offset);

}  // namespace fleetloc::geometry
