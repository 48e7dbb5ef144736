// The tracker agent's ROS 2 bridge, spoken on the ROS 2 wire without a ROS installation (rt/
// topic names, dds_ type names, ROS 2's default QoS: reliable, volatile, keep last): reads the
// vehicle's nav_msgs/Odometry and initialpose; writes the pose (PoseWithCovarianceStamped in map),
// the map → odom transform on tf (like AMCL) and DiagnosticArray from the agent's health.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "tracker_agent/live_config.h"
#include "transport/ros_messages.h"
#include "transport/typed_io.h"

namespace fleetloc::tracker_agent {

// ROS 2's default QoS (rmw_qos_profile_default): reliable, volatile, keep last `depth`.
transport::Qos RosDefaultQos(int depth = 10);

// The odometry stream alone (the live input reads it on its own participant).
class RosOdometryReader {
 public:
  static Result<std::unique_ptr<RosOdometryReader>> Create(
      const transport::Participant& participant, const RosOptions& options);
  // Every sample received since the last call, in arrival order.
  Result<std::vector<transport::RosOdometry>> Take();
  const std::string& topic_name() const { return topic_name_; }

 private:
  RosOdometryReader() = default;
  std::string topic_name_;
  std::unique_ptr<transport::Topic<nav_msgs_msg_dds__Odometry_>> topic_;
  std::unique_ptr<transport::Reader<nav_msgs_msg_dds__Odometry_>> reader_;
};

class RosBridge {
 public:
  static Result<std::unique_ptr<RosBridge>> Create(const transport::Participant& participant,
                                                   const RosOptions& options,
                                                   const std::string& vehicle_id);

  // base_link in map at `t` (its time of validity) on the pose topic.
  Status PublishPose(double t, const geometry::PoseWithCovariance& base_in_map);
  // map → odom at `t` from base_link in map and in odom at that time (if publish_tf).
  Status PublishMapToOdom(double t, const geometry::Pose2& base_in_map,
                          const geometry::Pose2& base_in_odom);
  Status PublishDiagnostics(double t, const fleetloc_VehicleHealth& health);
  // The newest initialpose received since the last call (in the map frame; others are refused
  // with a log line), nullopt when none.
  std::optional<transport::RosPoseStamped> TakeInitialPose();

 private:
  explicit RosBridge(RosOptions options, std::string vehicle_id)
      : options_(std::move(options)), vehicle_id_(std::move(vehicle_id)) {}
  RosOptions options_;
  std::string vehicle_id_;
  std::unique_ptr<transport::Topic<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>> pose_topic_,
      initial_topic_;
  std::unique_ptr<transport::Topic<tf2_msgs_msg_dds__TFMessage_>> tf_topic_;
  std::unique_ptr<transport::Topic<diagnostic_msgs_msg_dds__DiagnosticArray_>> diagnostics_topic_;
  std::unique_ptr<transport::Writer<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>>
      pose_writer_;
  std::unique_ptr<transport::Reader<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>>
      initial_reader_;
  std::unique_ptr<transport::Writer<tf2_msgs_msg_dds__TFMessage_>> tf_writer_;
  std::unique_ptr<transport::Writer<diagnostic_msgs_msg_dds__DiagnosticArray_>> diagnostics_writer_;
};

}  // namespace fleetloc::tracker_agent
