// Tests for the odometry noise model and covariance propagation.
#include "tracking/motion_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::tracking {
namespace {

TEST(MotionModel, AlongTrackSigmaScalesWithDistanceInTravelDirection) {
  OdometryNoiseOptions n;
  n.along_sigma_per_m = 0.01;
  n.lateral_sigma_per_m = 0.0;
  n.floor_sigma_m = 1e-12;
  // Driving 2 m along +y of the start frame: all position uncertainty is along y.
  const Eigen::Matrix3d q = IncrementCovariance({0.0, 2.0, 0.0}, 1.0, n);
  EXPECT_NEAR(std::sqrt(q(1, 1)), 0.02, 1e-9);
  EXPECT_NEAR(q(0, 0), 0.0, 1e-12);
}

TEST(MotionModel, PredictionAddsIncrementAndGrowsUncertainty) {
  OdometryNoiseOptions n;
  geometry::PoseWithCovariance start{{1.0, 1.0, M_PI / 2}, Eigen::Matrix3d::Identity() * 1e-8};
  const auto p = Predict(start, {0.5, 0.0, 0.1}, 0.2, n);
  EXPECT_NEAR(p.pose.x, 1.0, 1e-12);
  EXPECT_NEAR(p.pose.y, 1.5, 1e-12);
  EXPECT_NEAR(p.pose.theta, M_PI / 2 + 0.1, 1e-12);
  EXPECT_GT(p.covariance(1, 1), start.covariance(1, 1));
  EXPECT_GT(p.covariance(2, 2), start.covariance(2, 2));
}

TEST(MotionModel, ExtrapolationSigmaIsHalfTheAccelerationTimesTheSpanSquaredPlusTheLever) {
  OdometryNoiseOptions n;
  n.extrapolation_accel_m_s2 = 2.0;
  n.extrapolation_angular_accel_rad_s2 = 4.0;
  EXPECT_TRUE(ExtrapolationCovariance(0.0, 0.4, n).isZero());
  EXPECT_TRUE(ExtrapolationCovariance(-0.01, 0.4, n).isZero());
  // 20 ms: heading ½·4·0.02² = 0.8 mrad; position ½·2·0.02² = 0.4 mm + 0.4 m · 0.8 mrad.
  const Eigen::Matrix3d q = ExtrapolationCovariance(0.02, 0.4, n);
  EXPECT_NEAR(std::sqrt(q(2, 2)), 0.0008, 1e-12);
  EXPECT_NEAR(std::sqrt(q(0, 0)), 0.0004 + 0.4 * 0.0008, 1e-12);
  EXPECT_NEAR(std::sqrt(q(1, 1)), std::sqrt(q(0, 0)), 1e-15);
  // Twice the span: four times the sigma.
  EXPECT_NEAR(std::sqrt(ExtrapolationCovariance(0.04, 0.0, n)(0, 0)), 4 * 0.0004, 1e-12);
}

TEST(MotionModel, CameraIncrementOfATurnOnTheSpotMovesAMountedCamera) {
  OdometryNoiseOptions n;
  // base_link turns 90° on the spot; a camera 0.4 m ahead swings to 0.4 m left of where base_link
  // is, which in the camera's start frame is (-0.4, 0.4), turned by 90°.
  const geometry::PoseWithCovariance c = CameraIncrement(
      {1.0, 2.0, 0.3}, geometry::Pose2{1.0, 2.0, 0.3} * geometry::Pose2{0, 0, M_PI / 2}, 0.5,
      {0.4, 0.0, 0.0}, n);
  EXPECT_NEAR(c.pose.x, -0.4, 1e-12);
  EXPECT_NEAR(c.pose.y, 0.4, 1e-12);
  EXPECT_NEAR(c.pose.theta, M_PI / 2, 1e-12);
  // base_link does not move, so its heading error alone moves the camera, across the lever: the
  // lever ends along +y of the camera's start frame, and a further turn δθ moves the camera by
  // −0.4·δθ in x.
  const double heading_sigma =
      n.heading_sigma_per_rad * M_PI / 2 + n.heading_sigma_per_s * 0.5 + n.floor_sigma_m;
  EXPECT_NEAR(std::sqrt(c.covariance(2, 2)), heading_sigma, 1e-12);
  EXPECT_NEAR(std::sqrt(c.covariance(0, 0)), 0.4 * heading_sigma, 1e-5);
  EXPECT_LT(std::sqrt(c.covariance(1, 1)), 2e-5);  // the floor sigma only
  EXPECT_NEAR(c.covariance(0, 2), -0.4 * heading_sigma * heading_sigma, 1e-8);
}

}  // namespace
}  // namespace fleetloc::tracking
