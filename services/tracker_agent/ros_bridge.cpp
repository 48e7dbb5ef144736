// ROS 2 topics of the tracker agent over Cyclone DDS.
#include "tracker_agent/ros_bridge.h"

#include <spdlog/spdlog.h>

namespace fleetloc::tracker_agent {

transport::Qos RosDefaultQos(int depth) {
  return transport::Qos().Reliable().Volatile().KeepLast(depth);
}

Result<std::unique_ptr<RosOdometryReader>> RosOdometryReader::Create(
    const transport::Participant& p, const RosOptions& options) {
  std::unique_ptr<RosOdometryReader> r(new RosOdometryReader());
  r->topic_name_ = RosTopicName(options.ns, options.odom_topic);
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<nav_msgs_msg_dds__Odometry_>::Create(p, r->topic_name_), &r->topic_));
  // Deeper than ROS's 10 so a burst between two takes is not lost (depth does not affect matching).
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Reader<nav_msgs_msg_dds__Odometry_>::Create(
                                        p.get(), *r->topic_, RosDefaultQos(options.odom_history)),
                                    &r->reader_));
  return r;
}

Result<std::vector<transport::RosOdometry>> RosOdometryReader::Take() {
  std::vector<transport::RosOdometry> out;
  Result<int> taken =
      reader_->TakeAll([&](const nav_msgs_msg_dds__Odometry_& odometry, const dds_sample_info_t&) {
        out.push_back(transport::FromIdl(odometry));
      });
  if (!taken.ok()) return taken.status();
  return out;
}

Result<std::unique_ptr<RosBridge>> RosBridge::Create(const transport::Participant& p,
                                                     const RosOptions& options,
                                                     const std::string& vehicle_id) {
  std::unique_ptr<RosBridge> b(new RosBridge(options, vehicle_id));
  using PoseMsg = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;
  const std::string& ns = options.ns;
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<PoseMsg>::Create(p, RosTopicName(ns, options.pose_topic)), &b->pose_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Topic<PoseMsg>::Create(p, RosTopicName(ns, options.initialpose_topic)),
               &b->initial_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<tf2_msgs_msg_dds__TFMessage_>::Create(p, RosTopicName(ns, options.tf_topic)),
      &b->tf_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Topic<diagnostic_msgs_msg_dds__DiagnosticArray_>::Create(
                   p, RosTopicName(ns, options.diagnostics_topic)),
               &b->diagnostics_topic_));
  const transport::Qos qos = RosDefaultQos();
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Writer<PoseMsg>::Create(p.get(), *b->pose_topic_, qos), &b->pose_writer_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Reader<PoseMsg>::Create(p.get(), *b->initial_topic_, qos), &b->initial_reader_));
  // tf2's TransformBroadcaster: keep last 100.
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Writer<tf2_msgs_msg_dds__TFMessage_>::Create(
                                        p.get(), *b->tf_topic_, RosDefaultQos(100)),
                                    &b->tf_writer_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Writer<diagnostic_msgs_msg_dds__DiagnosticArray_>::Create(
                   p.get(), *b->diagnostics_topic_, qos),
               &b->diagnostics_writer_));
  spdlog::info(
      "ROS 2: odometry from {}, pose to {}, map->odom to {}, initial pose from {}, diagnostics to "
      "{}",
      RosTopicName(ns, options.odom_topic), b->pose_topic_->name(), b->tf_topic_->name(),
      b->initial_topic_->name(), b->diagnostics_topic_->name());
  return b;
}

Status RosBridge::PublishPose(double t, const geometry::PoseWithCovariance& base_in_map) {
  const transport::RosPoseMessage message(t, options_.map_frame, base_in_map);
  return pose_writer_->Write(message.get());
}

Status RosBridge::PublishMapToOdom(double t, const geometry::Pose2& base_in_map,
                                   const geometry::Pose2& base_in_odom) {
  if (!options_.publish_tf) return Status::Ok();
  const transport::RosTransformMessage message(t, options_.map_frame, options_.odom_frame,
                                               transport::MapToOdom(base_in_map, base_in_odom));
  return tf_writer_->Write(message.get());
}

Status RosBridge::PublishDiagnostics(double t, const fleetloc_VehicleHealth& health) {
  const transport::RosDiagnosticsMessage message(t, "fleetloc/" + vehicle_id_, health);
  return diagnostics_writer_->Write(message.get());
}

std::optional<transport::RosPoseStamped> RosBridge::TakeInitialPose() {
  std::optional<transport::RosPoseStamped> newest;
  (void)initial_reader_->TakeAll(
      [&](const geometry_msgs_msg_dds__PoseWithCovarianceStamped_& m, const dds_sample_info_t&) {
        transport::RosPoseStamped pose = transport::FromIdl(m);
        if (!pose.finite) {
          spdlog::warn("initial pose refused: not finite");
        } else if (pose.frame_id != options_.map_frame && !pose.frame_id.empty()) {
          spdlog::warn("initial pose refused: in frame '{}', not '{}'", pose.frame_id,
                       options_.map_frame);
        } else {
          newest = pose;
        }
      });
  return newest;
}

}  // namespace fleetloc::tracker_agent
