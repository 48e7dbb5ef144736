// Tests for SE(2) composition, inverse and Jacobians against closed forms and finite differences.
#include "geometry/pose2.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::geometry {
namespace {

TEST(WrapAngle, MapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(WrapAngle(-M_PI), M_PI);
  EXPECT_NEAR(WrapAngle(3 * M_PI / 2), -M_PI / 2, 1e-12);
  EXPECT_NEAR(WrapAngle(-7.0), -7.0 + 2 * M_PI, 1e-12);
}

TEST(Pose2, ComposeMatchesHandComputedExample) {
  const Pose2 a{1.0, 2.0, M_PI / 2};
  const Pose2 b{3.0, 0.5, 0.25};
  const Pose2 c = a * b;
  EXPECT_NEAR(c.x, 1.0 - 0.5, 1e-12);
  EXPECT_NEAR(c.y, 2.0 + 3.0, 1e-12);
  EXPECT_NEAR(c.theta, M_PI / 2 + 0.25, 1e-12);
}

TEST(Pose2, InverseComposesToIdentity) {
  const Pose2 a{-4.0, 0.3, 2.9};
  const Pose2 i = a * a.Inverse();
  EXPECT_NEAR(i.x, 0, 1e-12);
  EXPECT_NEAR(i.y, 0, 1e-12);
  EXPECT_NEAR(i.theta, 0, 1e-12);
  const Pose2 d = Between(a, a * Pose2{0.1, -0.2, 0.3});
  EXPECT_NEAR(d.x, 0.1, 1e-12);
  EXPECT_NEAR(d.y, -0.2, 1e-12);
  EXPECT_NEAR(d.theta, 0.3, 1e-12);
}

TEST(Pose2, PointTransformAgreesWithComposition) {
  const Pose2 a{1.5, -2.0, -0.7};
  const Eigen::Vector2d p(0.4, 0.9);
  const Pose2 c = a * Pose2{p.x(), p.y(), 0};
  const Eigen::Vector2d q = a * p;
  EXPECT_NEAR(q.x(), c.x, 1e-12);
  EXPECT_NEAR(q.y(), c.y, 1e-12);
}

Eigen::Matrix3d NumericJacobian(const Pose2& a, const Pose2& b, bool wrt_a) {
  Eigen::Matrix3d j;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const Pose2 ap = wrt_a ? Pose2::FromVector(a.ToVector() + d) : a;
    const Pose2 bp = wrt_a ? b : Pose2::FromVector(b.ToVector() + d);
    const Pose2 am = wrt_a ? Pose2::FromVector(a.ToVector() - d) : a;
    const Pose2 bm = wrt_a ? b : Pose2::FromVector(b.ToVector() - d);
    Eigen::Vector3d diff = (ap * bp).ToVector() - (am * bm).ToVector();
    diff.z() = WrapAngle(diff.z());
    j.col(k) = diff / (2 * h);
  }
  return j;
}

TEST(Pose2, ComposeJacobiansMatchFiniteDifferences) {
  const Pose2 a{0.3, -1.2, 1.1};
  const Pose2 b{2.0, 0.7, -0.4};
  EXPECT_TRUE(ComposeJacobianA(a, b).isApprox(NumericJacobian(a, b, true), 1e-6));
  EXPECT_TRUE(ComposeJacobianB(a).isApprox(NumericJacobian(a, b, false), 1e-6));
}

TEST(Pose2, PointJacobianMatchesFiniteDifferences) {
  const Pose2 a{0.3, -1.2, 1.1};
  const Eigen::Vector2d p(0.5, -0.25);
  Eigen::Matrix<double, 2, 3> numeric;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = 1e-6;
    numeric.col(k) =
        (Pose2::FromVector(a.ToVector() + d) * p - Pose2::FromVector(a.ToVector() - d) * p) / 2e-6;
  }
  EXPECT_TRUE(PointJacobian(a, p).isApprox(numeric, 1e-6));
}

TEST(PoseWithCovariance, HeadingUncertaintyGrowsLateralVarianceWithLeverArm) {
  PoseWithCovariance a{{0, 0, 0}, Eigen::Matrix3d::Zero()};
  a.covariance(2, 2) = 0.01 * 0.01;  // 0.01 rad
  const PoseWithCovariance c = ComposeFixed(a, Pose2{2.0, 0, 0});
  // A 2 m lever arm turns 0.01 rad into 0.02 m of lateral (y) standard deviation.
  EXPECT_NEAR(std::sqrt(c.covariance(1, 1)), 0.02, 1e-12);
  EXPECT_NEAR(c.covariance(0, 0), 0.0, 1e-15);
  const PoseWithCovariance sum = Compose(a, {{1, 0, 0}, Eigen::Matrix3d::Identity() * 1e-4});
  EXPECT_NEAR(sum.covariance(0, 0), 1e-4, 1e-15);
  EXPECT_NEAR(sum.covariance(1, 1), 1e-4 + 1e-4, 1e-12);
}

}  // namespace
}  // namespace fleetloc::geometry
