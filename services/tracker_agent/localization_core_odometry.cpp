// LocalizationCore's odometry: samples that release waiting frames and propagate the pose, a
// timeline that restarts, start poses given by the vehicle, frames run on odometry extrapolated
// past its newest sample, and map -> odom once odometry covers a pose's time.
#include <spdlog/spdlog.h>

#include <cmath>

#include "tracker_agent/initial_pose_anchor.h"
#include "tracker_agent/localization_core.h"

namespace fleetloc::tracker_agent {

void LocalizationCore::OnOdometry(double t, const geometry::Pose2& odom) {
  if (Status added = odometry_.Add({t, odom}); !added.ok()) {
    health_.RecordError("odometry at t=" + std::to_string(t) + ": " + added.message());
    return;  // a NaN or out-of-order sample is dropped, counted in the last error
  }
  latest_odometry_t_ = t;
  CorrectExtrapolatedOdometry();
  PublishDeferredMapToOdom();
  if (restart_pose_) {  // the first sample of a new odometry timeline
    tracker_.Reset(*restart_pose_, odom);
    propagator_.SetAnchor(t, odom, *std::exchange(restart_pose_, std::nullopt));
  }
  if (pending_initial_) {
    const auto [stamp, pose] = *pending_initial_;
    ApplyInitialPose(stamp, pose);
  }
  ProcessReadyFrames();
  if (propagator_.anchored() && t > propagator_.anchor_time()) {
    Publish(t, propagator_.At(t, odom), state_, PoseOrigin::kOdometry);
  }
}

void LocalizationCore::PublishMapToOdom(double t, const geometry::Pose2& base) {
  if (t > latest_odometry_t_) {  // a frame run on extrapolated odometry
    deferred_map_to_odom_.emplace_back(t, base);
    if (deferred_map_to_odom_.size() > 16) deferred_map_to_odom_.pop_front();
    return;
  }
  const Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return;
  ports_.poses->PublishMapToOdom(t, base, *odom);
}

void LocalizationCore::PublishDeferredMapToOdom() {
  while (!deferred_map_to_odom_.empty() &&
         deferred_map_to_odom_.front().first <= latest_odometry_t_) {
    const auto [t, base] = deferred_map_to_odom_.front();
    deferred_map_to_odom_.pop_front();
    const Result<geometry::Pose2> odom = odometry_.At(t);
    if (!odom.ok()) continue;
    ports_.poses->PublishMapToOdom(t, base, *odom);
  }
}

void LocalizationCore::ApplyInitialPose(double stamp, const geometry::PoseWithCovariance& pose) {
  if (odometry_.empty()) {
    pending_initial_.emplace(stamp, pose);  // anchored when odometry comes
    return;
  }
  pending_initial_.reset();
  // Anchored to recorded odometry, never to extrapolated; refused when older than the history.
  const InitialPoseAnchor anchor = AnchorInitialPose(stamp, odometry_, latest_odometry_t_);
  if (!anchor.ok) {
    spdlog::warn("initial pose from {} refused: {}", options_.initial_pose_source, anchor.reason);
    return health_.RecordError("initial pose: " + anchor.reason);
  }
  const double t = anchor.t;
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return health_.RecordError("initial pose: " + odom.status().message());
  spdlog::info("initial pose from {}: ({:.4f}, {:.4f}, {:.2f} deg) at t={:.3f}",
               options_.initial_pose_source, pose.pose.x, pose.pose.y,
               pose.pose.theta * 180.0 / M_PI, t);
  initial_ = pose;
  WarmUp(t, pose);
  tracker_.Reset(pose, *odom);
  extrapolated_frame_t_.reset();
  started_ = true;
  provisional_ = false;
  coasting_in_a_row_ = 0;
  if (position_update_) position_update_->Forget();
  state_ = tracking::LockState::kCoasting;  // until a frame tracks from it
  health_.RecordLockState(state_);
  propagator_.SetAnchor(t, *odom, pose);
  Publish(t, pose, state_, PoseOrigin::kGiven);
}

void LocalizationCore::OnOdometryRestart() {
  if (propagator_.anchored() && !odometry_.empty()) {
    const Result<geometry::Pose2> last = odometry_.At(latest_odometry_t_);
    if (last.ok()) restart_pose_ = propagator_.At(latest_odometry_t_, *last);
  }
  spdlog::warn(
      "odometry restarted: {} frames waiting on the old timeline dropped; tracking continues "
      "from the last pose",
      waiting_frames_.size());
  for (size_t i = 0; i < waiting_frames_.size(); ++i)
    health_.RecordDroppedFrame("odometry restarted");
  waiting_frames_.clear();
  odometry_ = tracking::OdometryHistory(10.0, extrapolation_s_);
  latest_odometry_t_ = -1e300;
  extrapolated_frame_t_.reset();
  deferred_map_to_odom_.clear();
}

bool LocalizationCore::FrameReady(double t) const {
  if (t <= latest_odometry_t_) return true;
  // Constant-velocity extrapolation needs a velocity: two samples of the current timeline.
  return extrapolation_s_ > 0 && odometry_.size() >= 2 &&
         t - latest_odometry_t_ <= extrapolation_s_;
}

void LocalizationCore::CorrectExtrapolatedOdometry() {
  if (!extrapolated_frame_t_ || *extrapolated_frame_t_ > latest_odometry_t_) return;
  const double t = *std::exchange(extrapolated_frame_t_, std::nullopt);
  const Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return;
  tracker_.CorrectOdometry(t, *odom);
  propagator_.CorrectAnchorOdometry(t, *odom);
}

std::string LocalizationCore::InOdometryGap(double t) const {
  if (!options_.live) return "";  // recorded runs: as fleetctl track does
  const double gap = odometry_.GapAround(t);
  if (gap <= options_.odometry_stale_s) return "";
  return "frame at t=" + std::to_string(t) +
         " captured while odometry had stopped (no sample for " + std::to_string(gap) + " s)";
}

}  // namespace fleetloc::tracker_agent
