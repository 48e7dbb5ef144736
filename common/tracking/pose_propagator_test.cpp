// Pose propagation: exact at the anchor, follows the odometry increment, uncertainty grows.
#include "tracking/pose_propagator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::tracking {
namespace {

TEST(PosePropagator, AddsTheOdometryIncrementToTheAnchorAndGrowsTheCovariance) {
  PosePropagator propagator({});
  const geometry::Pose2 odom0{10.0, -3.0, 0.4};
  const geometry::PoseWithCovariance base{{1.0, 2.0, M_PI / 2}, Eigen::Matrix3d::Identity() * 1e-8};
  propagator.SetAnchor(5.0, odom0, base);
  const geometry::PoseWithCovariance same = propagator.At(5.0, odom0);
  EXPECT_NEAR(same.pose.x, 1.0, 1e-12);
  EXPECT_NEAR(same.pose.y, 2.0, 1e-12);
  // 0.5 m forward in odom (along its heading 0.4 rad) is 0.5 m along base's heading (+y) in map.
  const geometry::Pose2 odom1 = odom0 * geometry::Pose2{0.5, 0.0, 0.1};
  const geometry::PoseWithCovariance moved = propagator.At(5.5, odom1);
  EXPECT_NEAR(moved.pose.x, 1.0, 1e-12);
  EXPECT_NEAR(moved.pose.y, 2.5, 1e-12);
  EXPECT_NEAR(moved.pose.theta, M_PI / 2 + 0.1, 1e-12);
  EXPECT_GT(moved.covariance(0, 0) + moved.covariance(1, 1), 2e-8 + 1e-7);
}

TEST(PosePropagator, AnAnchorSetOnExtrapolatedOdometryPropagatesFromTheTrueOdometryOnceKnown) {
  PosePropagator propagator({});
  const geometry::PoseWithCovariance base{{1.0, 2.0, 0.0}, Eigen::Matrix3d::Identity() * 1e-8};
  const geometry::Pose2 extrapolated{0.30, 0.0, 0.0}, truth{0.29, 0.0, 0.0};
  propagator.SetAnchor(1.0, extrapolated, base);
  propagator.CorrectAnchorOdometry(0.9, truth);  // not the anchor's time: ignored
  EXPECT_NEAR(propagator.At(1.1, {0.40, 0.0, 0.0}).pose.x, 1.10, 1e-12);
  propagator.CorrectAnchorOdometry(1.0, truth);
  EXPECT_NEAR(propagator.At(1.1, {0.40, 0.0, 0.0}).pose.x, 1.11, 1e-12);
}

}  // namespace
}  // namespace fleetloc::tracking
