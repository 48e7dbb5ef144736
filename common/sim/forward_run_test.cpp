// The simulated forward-camera drive: a route inside the corridor heading along its tangent,
// frames at the frame rate, odometry that starts on the truth and drifts away slowly.
#include "sim/forward_run.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::sim {
namespace {

TEST(ForwardRun, TheRouteWeavesInsideTheCorridorHeadingAlongItsTangent) {
  const ForwardRunOptions options;
  for (double t = 0; t <= 19.5; t += 0.25) {
    const geometry::Pose2 pose = ForwardRoutePose(options, t);
    EXPECT_LE(std::abs(pose.y), options.weave_amplitude_m + 1e-12);
    const geometry::Pose2 next = ForwardRoutePose(options, t + 1e-6);
    EXPECT_NEAR(std::atan2(next.y - pose.y, next.x - pose.x), pose.theta, 1e-5);
  }
}

TEST(ForwardRun, PlanHasFramesAtTheRateAndDriftingOdometry) {
  ForwardRunOptions options;
  const ForwardRunPlan plan = PlanForwardRun(options);
  ASSERT_EQ(plan.frame_truth.size(), 40u);
  EXPECT_DOUBLE_EQ(plan.frame_truth[1].t, 0.5);
  EXPECT_DOUBLE_EQ(plan.frame_truth.back().t, 19.5);
  ASSERT_EQ(plan.odometry.size(), 391u);  // 20 Hz over 19.5 s
  EXPECT_NEAR(plan.odometry.front().pose.x, plan.frame_truth.front().pose.x, 1e-12)
      << "odom starts aligned with the truth";
  // 7.8 m of travel with 1 % scale errors and 0.2°/s of heading drift: centimetres to decimetres.
  const geometry::Pose2 odom_move =
      geometry::Between(plan.odometry.front().pose, plan.odometry.back().pose);
  const geometry::Pose2 true_move =
      geometry::Between(plan.frame_truth.front().pose, plan.frame_truth.back().pose);
  const double drift = std::hypot(odom_move.x - true_move.x, odom_move.y - true_move.y);
  EXPECT_GT(drift, 0.01);
  EXPECT_LT(drift, 0.5);
}

TEST(ForwardRun, ADriveIntoTheEndWallIsRefused) {
  ForwardRunOptions options;
  options.frames = 200;
  const Status status = Validate(options);
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput);
  EXPECT_NE(status.message().find("end wall"), std::string::npos) << status.message();
}

}  // namespace
}  // namespace fleetloc::sim
