// TrackerAgent on a live vehicle: poses and map -> odom out to the vehicle's ROS 2 stack (with the
// capture -> pose latency), a start pose from its initialpose, odometry that restarts.
#include <spdlog/spdlog.h>

#include "camera_io/camera_source.h"
#include "tracker_agent/tracker_agent.h"

namespace fleetloc::tracker_agent {

void TrackerAgent::PublishRos(double t, const geometry::PoseWithCovariance& base, bool propagated) {
  if (!propagated) {
    if (Status sent = ros_->PublishPose(t, base); !sent.ok()) health_.RecordError(sent.message());
    if (IsLiveSource(config_.source)) {  // t is the frame's capture time on the host clock
      capture_to_pose_ms_.push_back((camera_io::HostNow() - t) * 1000.0);
      if (capture_to_pose_ms_.size() > 10000) capture_to_pose_ms_.pop_front();
    }
  }
  const Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return;
  if (Status sent = ros_->PublishMapToOdom(t, base.pose, *odom); !sent.ok())
    health_.RecordError(sent.message());
}

void TrackerAgent::ApplyInitialPose(const transport::RosPoseStamped& given) {
  if (odometry_.empty()) {
    pending_initial_ = given;  // anchored when odometry comes
    return;
  }
  pending_initial_.reset();
  double t = given.t;
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) t = latest_odometry_t_, odom = odometry_.At(t);
  if (!odom.ok()) return health_.RecordError("initial pose: " + odom.status().message());
  spdlog::info("initial pose from {}: ({:.4f}, {:.4f}, {:.2f} deg) at t={:.3f}",
               config_.ros.initialpose_topic, given.pose.pose.x, given.pose.pose.y,
               given.pose.pose.theta * 180.0 / M_PI, t);
  initial_ = given.pose;
  tracker_->Reset(given.pose, *odom);
  started_ = true, provisional_ = false, coasting_in_a_row_ = 0;
  if (position_update_) position_update_->Forget();
  state_ = tracking::LockState::kCoasting;  // until a frame tracks from it
  health_.RecordLockState(state_);
  propagator_->SetAnchor(t, *odom, given.pose);
  Publish(t, given.pose, state_);
}

void TrackerAgent::OnOdometryRestart() {
  if (propagator_->anchored() && !odometry_.empty()) {
    const Result<geometry::Pose2> last = odometry_.At(latest_odometry_t_);
    if (last.ok()) restart_pose_ = propagator_->At(latest_odometry_t_, *last);
  }
  spdlog::warn(
      "odometry restarted: {} frames waiting on the old timeline dropped; tracking continues "
      "from the last pose",
      waiting_frames_.size());
  for (size_t i = 0; i < waiting_frames_.size(); ++i)
    health_.RecordDroppedFrame("odometry restarted");
  waiting_frames_.clear();
  odometry_ = tracking::OdometryHistory(10.0, 0.0);
  latest_odometry_t_ = -1e300;
}

}  // namespace fleetloc::tracker_agent
