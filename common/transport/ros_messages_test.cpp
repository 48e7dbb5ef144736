// ROS 2 message conversions: yaw ↔ quaternion, 3×3 ↔ 6×6 covariance, map → odom, time, NaN
// odometry flagged, diagnostics carrying every health issue.
#include "transport/ros_messages.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

TEST(RosMessages, PoseOutCarriesYawAndThe3x3CovarianceAtXYYaw) {
  geometry::PoseWithCovariance pose{{1.5, -2.0, 2.8}, Eigen::Matrix3d::Zero()};
  pose.covariance << 4e-6, 1e-7, 2e-7, 1e-7, 9e-6, 3e-7, 2e-7, 3e-7, 1e-4;
  const RosPoseMessage message(1700000000.25, "map", pose);
  const auto& m = message.get();
  EXPECT_EQ(m.header.stamp.sec, 1700000000);
  EXPECT_EQ(m.header.stamp.nanosec, 250000000u);
  EXPECT_STREQ(m.header.frame_id, "map");
  EXPECT_NEAR(YawOf(m.pose.pose.orientation), 2.8, 1e-12);
  EXPECT_EQ(m.pose.covariance[0], 4e-6);
  EXPECT_EQ(m.pose.covariance[1], 1e-7);
  EXPECT_EQ(m.pose.covariance[5], 2e-7);   // x-yaw
  EXPECT_EQ(m.pose.covariance[7], 9e-6);   // y-y
  EXPECT_EQ(m.pose.covariance[30], 2e-7);  // yaw-x
  EXPECT_EQ(m.pose.covariance[35], 1e-4);  // yaw-yaw
  EXPECT_EQ(m.pose.covariance[14], 0.0);   // z-z
  const RosPoseStamped back = FromIdl(m);
  EXPECT_TRUE(back.finite);
  EXPECT_EQ(back.frame_id, "map");
  EXPECT_NEAR(back.t, 1700000000.25, 1e-6);
  EXPECT_EQ((back.pose.covariance - pose.covariance).norm(), 0.0);
}

TEST(RosMessages, MapToOdomComposesBackToTheMapPose) {
  const geometry::Pose2 base_in_map{3.0, 1.0, 0.7}, base_in_odom{-0.5, 2.0, -1.2};
  const RosTransformMessage tf(10.0, "map", "odom", MapToOdom(base_in_map, base_in_odom));
  const auto& t = tf.get().transforms._buffer[0];
  ASSERT_EQ(tf.get().transforms._length, 1u);
  EXPECT_STREQ(t.header.frame_id, "map");
  EXPECT_STREQ(t.child_frame_id, "odom");
  const geometry::Pose2 odom_in_map{t.transform.translation.x, t.transform.translation.y,
                                    YawOf(t.transform.rotation)};
  const geometry::Pose2 again = odom_in_map * base_in_odom;
  EXPECT_NEAR(again.x, 3.0, 1e-12);
  EXPECT_NEAR(again.y, 1.0, 1e-12);
  EXPECT_NEAR(again.theta, 0.7, 1e-12);
}

TEST(RosMessages, OdometryWithNaNOrAZeroQuaternionIsNotFinite) {
  nav_msgs_msg_dds__Odometry_ odom{};
  odom.header.stamp = {12, 500000000};
  odom.pose.pose.position = {1.0, 2.0, 0.0};
  odom.pose.pose.orientation = QuaternionOfYaw(-0.3);
  RosOdometry ok = FromIdl(odom);
  EXPECT_TRUE(ok.finite);
  EXPECT_DOUBLE_EQ(ok.t, 12.5);
  EXPECT_NEAR(ok.pose.theta, -0.3, 1e-12);
  odom.pose.pose.position.x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(FromIdl(odom).finite);
  odom.pose.pose.position.x = 1.0;
  odom.pose.pose.orientation = {0, 0, 0, 0};
  EXPECT_FALSE(FromIdl(odom).finite);
}

TEST(RosMessages, DiagnosticsListEveryIssueWithItsLevel) {
  fleetloc_VehicleHealth h{};
  SetBounded(h.vehicle_id, "agv-3");
  h.level = fleetloc_HEALTH_WARN;
  h.lock_state = fleetloc_LOCK_TRACKING;
  h.camera_frame_drops = 7;
  fleetloc_HealthIssue issues[2]{};
  SetBounded(issues[0].name, "camera_frame_drops");
  issues[0].level = fleetloc_HEALTH_WARN;
  SetBounded(issues[0].message, "7 frames dropped");
  SetBounded(issues[1].name, "odometry_stale");
  issues[1].level = fleetloc_HEALTH_ERROR;
  SetBounded(issues[1].message, "no odometry for 1.2 s");
  h.issues._buffer = issues;
  h.issues._length = 2;
  const RosDiagnosticsMessage message(5.0, "fleetloc/agv-3", h);
  const auto& d = message.get();
  ASSERT_EQ(d.status._length, 3u);
  EXPECT_EQ(d.status._buffer[0].level, kDiagnosticWarn);
  EXPECT_STREQ(d.status._buffer[0].message, "camera_frame_drops, odometry_stale");
  EXPECT_STREQ(d.status._buffer[0].hardware_id, "agv-3");
  EXPECT_STREQ(d.status._buffer[2].name, "fleetloc/agv-3/odometry_stale");
  EXPECT_EQ(d.status._buffer[2].level, kDiagnosticError);
  EXPECT_STREQ(d.status._buffer[2].message, "no odometry for 1.2 s");
  bool drops = false;
  for (uint32_t i = 0; i < d.status._buffer[0].values._length; ++i) {
    const auto& kv = d.status._buffer[0].values._buffer[i];
    if (std::string(kv.key) == "camera_frame_drops") drops = std::string(kv.value) == "7";
  }
  EXPECT_TRUE(drops);
}

}  // namespace
}  // namespace fleetloc::transport
