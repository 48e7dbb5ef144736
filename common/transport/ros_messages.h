// Conversions between fleetloc's poses and health and the ROS 2 messages a vehicle's navigation
// stack speaks (REP-105 frames, REP-103 units): Odometry in, PoseWithCovarianceStamped and the
// map → odom transform out (like AMCL), initialpose in, DiagnosticArray from VehicleHealth.
// Planar: z = 0, roll = pitch = 0; the 3×3 (x, y, yaw) covariance sits at rows/columns 0, 1, 5 of
// ROS's 6×6 (x, y, z, roll, pitch, yaw), the others zero. Outgoing messages point into their
// owner's strings: keep the owner alive while writing.
#pragma once

#include <string>
#include <vector>

#include "geometry/pose2.h"
#include "transport/ros_types.h"

namespace fleetloc::transport {

// diagnostic_msgs/DiagnosticStatus levels (the .msg constants).
inline constexpr uint8_t kDiagnosticOk = 0, kDiagnosticWarn = 1, kDiagnosticError = 2,
                         kDiagnosticStale = 3;

builtin_interfaces_msg_dds__Time_ ToRosTime(double t_s);
double FromRosTime(const builtin_interfaces_msg_dds__Time_& time);

// Yaw of a (planar) quaternion, and the quaternion of a yaw.
double YawOf(const geometry_msgs_msg_dds__Quaternion_& q);
geometry_msgs_msg_dds__Quaternion_ QuaternionOfYaw(double yaw_rad);

// ROS's 6×6 (row-major) from the planar 3×3 and back.
void FillCovariance6(const Eigen::Matrix3d& covariance, double out[36]);
Eigen::Matrix3d Covariance3(const double covariance[36]);

struct RosOdometry {
  double t = 0.0;        // header stamp
  geometry::Pose2 pose;  // child frame (base_link) in the header frame (odom)
  bool finite = true;    // stamp, position and orientation all finite, quaternion not zero
};
RosOdometry FromIdl(const nav_msgs_msg_dds__Odometry_& odometry);

struct RosPoseStamped {
  double t = 0.0;
  std::string frame_id;
  geometry::PoseWithCovariance pose;
  bool finite = true;
};
RosPoseStamped FromIdl(const geometry_msgs_msg_dds__PoseWithCovarianceStamped_& pose);

// A PoseWithCovarianceStamped of base_link in `frame_id` at `t`.
class RosPoseMessage {
 public:
  RosPoseMessage(double t, const std::string& frame_id, const geometry::PoseWithCovariance& pose);
  const geometry_msgs_msg_dds__PoseWithCovarianceStamped_& get() const { return message_; }

 private:
  std::string frame_id_;
  geometry_msgs_msg_dds__PoseWithCovarianceStamped_ message_{};
};

// A TFMessage with one transform: `child` in `parent` at `t`.
class RosTransformMessage {
 public:
  RosTransformMessage(double t, const std::string& parent, const std::string& child,
                      const geometry::Pose2& child_in_parent);
  const tf2_msgs_msg_dds__TFMessage_& get() const { return message_; }

 private:
  std::string parent_, child_;
  geometry_msgs_msg_dds__TransformStamped_ transform_{};
  tf2_msgs_msg_dds__TFMessage_ message_{};
};

// map → odom as AMCL publishes it: base_link in map composed with the inverse of base_link in odom.
geometry::Pose2 MapToOdom(const geometry::Pose2& base_in_map, const geometry::Pose2& base_in_odom);

// A DiagnosticArray from a VehicleHealth: one status named `name` with the health's level,
// a message listing its issues, the vehicle id as hardware id and the figures as key/values;
// then one status per issue ("<name>/<issue>").
class RosDiagnosticsMessage {
 public:
  RosDiagnosticsMessage(double t, const std::string& name, const fleetloc_VehicleHealth& health);
  const diagnostic_msgs_msg_dds__DiagnosticArray_& get() const { return message_; }

 private:
  struct Entry {
    uint8_t level = kDiagnosticOk;
    std::string name, message;
    std::vector<std::pair<std::string, std::string>> values;
  };
  std::vector<Entry> statuses_;
  std::string hardware_id_;
  std::vector<std::vector<diagnostic_msgs_msg_dds__KeyValue_>> values_;
  std::vector<diagnostic_msgs_msg_dds__DiagnosticStatus_> status_;
  diagnostic_msgs_msg_dds__DiagnosticArray_ message_{};
  std::string empty_;
};

}  // namespace fleetloc::transport
