// ROS 2 message conversions (planar poses, 6×6 covariances, diagnostics).
#include "transport/ros_messages.h"

#include <cmath>
#include <cstdio>

#include "transport/pose_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

constexpr int kIndex[3] = {0, 1, 5};  // x, y, yaw in ROS's (x, y, z, roll, pitch, yaw)

char* Chars(const std::string& s) { return const_cast<char*>(s.c_str()); }

std::string Figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", value);
  return text;
}

const char* LevelName(uint8_t level) {
  static const char* names[] = {"OK", "WARN", "ERROR", "STALE"};
  return level <= kDiagnosticStale ? names[level] : "?";
}

}  // namespace

builtin_interfaces_msg_dds__Time_ ToRosTime(double t_s) {
  double sec = std::floor(t_s);
  auto nanosec = static_cast<uint32_t>(std::llround((t_s - sec) * 1e9));
  if (nanosec >= 1000000000u) {
    sec += 1;
    nanosec -= 1000000000u;
  }
  return {static_cast<int32_t>(sec), nanosec};
}

double FromRosTime(const builtin_interfaces_msg_dds__Time_& time) {
  return static_cast<double>(time.sec) + static_cast<double>(time.nanosec) * 1e-9;
}

double YawOf(const geometry_msgs_msg_dds__Quaternion_& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

geometry_msgs_msg_dds__Quaternion_ QuaternionOfYaw(double yaw_rad) {
  return {0.0, 0.0, std::sin(yaw_rad / 2), std::cos(yaw_rad / 2)};
}

void FillCovariance6(const Eigen::Matrix3d& covariance, double out[36]) {
  for (int i = 0; i < 36; ++i) out[i] = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[6 * kIndex[r] + kIndex[c]] = covariance(r, c);
}

Eigen::Matrix3d Covariance3(const double covariance[36]) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = covariance[6 * kIndex[r] + kIndex[c]];
  return out;
}

namespace {

bool FinitePose(const geometry_msgs_msg_dds__Pose_& p) {
  const auto& q = p.orientation;
  const double norm = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  return std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(norm) &&
         norm > 1e-12;
}

}  // namespace

RosOdometry FromIdl(const nav_msgs_msg_dds__Odometry_& odometry) {
  const geometry_msgs_msg_dds__Pose_& p = odometry.pose.pose;
  RosOdometry out;
  out.t = FromRosTime(odometry.header.stamp);
  out.finite = FinitePose(p);
  out.pose = out.finite ? geometry::Pose2{p.position.x, p.position.y, YawOf(p.orientation)}
                        : geometry::Pose2{};
  return out;
}

RosPoseStamped FromIdl(const geometry_msgs_msg_dds__PoseWithCovarianceStamped_& pose) {
  const geometry_msgs_msg_dds__Pose_& p = pose.pose.pose;
  RosPoseStamped out;
  out.t = FromRosTime(pose.header.stamp);
  out.frame_id = pose.header.frame_id ? pose.header.frame_id : "";
  out.finite = FinitePose(p);
  if (!out.finite) return out;
  out.pose.pose = {p.position.x, p.position.y, YawOf(p.orientation)};
  out.pose.covariance = Covariance3(pose.pose.covariance);
  out.finite = out.pose.covariance.allFinite();
  return out;
}

RosPoseMessage::RosPoseMessage(double t, const std::string& frame_id,
                               const geometry::PoseWithCovariance& pose)
    : frame_id_(frame_id) {
  message_.header.stamp = ToRosTime(t);
  message_.header.frame_id = Chars(frame_id_);
  message_.pose.pose.position = {pose.pose.x, pose.pose.y, 0.0};
  message_.pose.pose.orientation = QuaternionOfYaw(pose.pose.theta);
  FillCovariance6(pose.covariance, message_.pose.covariance);
}

RosTransformMessage::RosTransformMessage(double t, const std::string& parent,
                                         const std::string& child,
                                         const geometry::Pose2& child_in_parent)
    : parent_(parent), child_(child) {
  transform_.header.stamp = ToRosTime(t);
  transform_.header.frame_id = Chars(parent_);
  transform_.child_frame_id = Chars(child_);
  transform_.transform.translation = {child_in_parent.x, child_in_parent.y, 0.0};
  transform_.transform.rotation = QuaternionOfYaw(child_in_parent.theta);
  message_.transforms._buffer = &transform_;
  message_.transforms._length = message_.transforms._maximum = 1;
  message_.transforms._release = false;
}

geometry::Pose2 MapToOdom(const geometry::Pose2& base_in_map, const geometry::Pose2& base_in_odom) {
  return base_in_map * base_in_odom.Inverse();
}

RosDiagnosticsMessage::RosDiagnosticsMessage(double t, const std::string& name,
                                             const fleetloc_VehicleHealth& h)
    : hardware_id_(GetBounded(h.vehicle_id)) {
  Entry summary;
  summary.level = static_cast<uint8_t>(h.level);  // fleetloc's levels are ROS's (OK .. STALE)
  summary.name = name;
  summary.values = {{"lock_state", tracking::LockStateName(FromIdl(h.lock_state))},
                    {"inliers", std::to_string(h.inliers)},
                    {"cycle_ms_p50", Figure(h.cycle_ms_p50)},
                    {"cycle_ms_p99", Figure(h.cycle_ms_p99)},
                    {"camera_frame_drops", std::to_string(h.camera_frame_drops)},
                    {"map_server_reachable", h.map_server_reachable ? "true" : "false"}};
  for (uint32_t i = 0; i < h.issues._length; ++i) {
    const fleetloc_HealthIssue& issue = h.issues._buffer[i];
    summary.message += (summary.message.empty() ? "" : ", ") + GetBounded(issue.name);
    statuses_.push_back({static_cast<uint8_t>(issue.level),
                         name + "/" + GetBounded(issue.name),
                         GetBounded(issue.message),
                         {}});
  }
  if (summary.message.empty())
    summary.message = std::string(LevelName(summary.level)) + ": localizing";
  statuses_.insert(statuses_.begin(), std::move(summary));
  values_.resize(statuses_.size());
  for (size_t i = 0; i < statuses_.size(); ++i) {
    Entry& s = statuses_[i];
    for (auto& [key, value] : s.values) values_[i].push_back({Chars(key), Chars(value)});
    diagnostic_msgs_msg_dds__DiagnosticStatus_ status{};
    status.level = s.level;
    status.name = Chars(s.name);
    status.message = Chars(s.message);
    status.hardware_id = Chars(hardware_id_);
    status.values._buffer = values_[i].data();
    status.values._length = status.values._maximum = static_cast<uint32_t>(values_[i].size());
    status_.push_back(status);
  }
  message_.header.stamp = ToRosTime(t);
  message_.header.frame_id = Chars(empty_);
  message_.status._buffer = status_.data();
  message_.status._length = message_.status._maximum = static_cast<uint32_t>(status_.size());
}

}  // namespace fleetloc::transport
