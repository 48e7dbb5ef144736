// SE(2) pose algebra.
#include "geometry/pose2.h"

#include <cmath>

namespace fleetloc::geometry {

double WrapAngle(double angle_rad) {
  double a = std::remainder(angle_rad, 2.0 * M_PI);  // in [-pi, pi]
  if (a <= -M_PI) a += 2.0 * M_PI;
  return a;
}

Pose2 Pose2::operator*(const Pose2& other) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {x + c * other.x - s * other.y, y + s * other.x + c * other.y,
          WrapAngle(theta + other.theta)};
}

Pose2 Pose2::Inverse() const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {-c * x - s * y, s * x - c * y, WrapAngle(-theta)};
}

Eigen::Vector2d Pose2::operator*(const Eigen::Vector2d& p) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
}

Eigen::Vector3d Difference(const Pose2& a, const Pose2& b) {
  return {a.x - b.x, a.y - b.y, WrapAngle(a.theta - b.theta)};
}

Pose2 Between(const Pose2& a, const Pose2& b) { return a.Inverse() * b; }

Eigen::Matrix3d ComposeJacobianA(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j(0, 2) = -s * b.x - c * b.y;
  j(1, 2) = c * b.x - s * b.y;
  return j;
}

Eigen::Matrix3d ComposeJacobianB(const Pose2& a) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j.topLeftCorner<2, 2>() << c, -s, s, c;
  return j;
}

Eigen::Matrix<double, 2, 3> PointJacobian(const Pose2& pose, const Eigen::Vector2d& p) {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  Eigen::Matrix<double, 2, 3> j;
  j << 1, 0, -s * p.x() - c * p.y(),  //
      0, 1, c * p.x() - s * p.y();
  return j;
}

PoseWithCovariance Compose(const PoseWithCovariance& a, const PoseWithCovariance& b) {
  const Eigen::Matrix3d ja = ComposeJacobianA(a.pose, b.pose);
  const Eigen::Matrix3d jb = ComposeJacobianB(a.pose);
  return {a.pose * b.pose, ja * a.covariance * ja.transpose() + jb * b.covariance * jb.transpose()};
}

PoseWithCovariance ComposeFixed(const PoseWithCovariance& a, const Pose2& offset) {
  const Eigen::Matrix3d ja = ComposeJacobianA(a.pose, offset);
  return {a.pose * offset, ja * a.covariance * ja.transpose()};
}

}  // namespace fleetloc::geometry
