// TrackerAgent on a live vehicle: poses and map -> odom out to the vehicle's ROS 2 stack (with the
// capture -> pose latency), a start pose from its initialpose (tiles around it fetched ahead),
// odometry that restarts, frames run on odometry extrapolated past its newest sample.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "camera_io/camera_source.h"
#include "replay/replay.h"
#include "tracker_agent/initial_pose_anchor.h"
#include "tracker_agent/tracker_agent.h"

namespace fleetloc::tracker_agent {

void TrackerAgent::PublishRos(double t, const geometry::PoseWithCovariance& base,
                              PoseOrigin origin) {
  if (origin != PoseOrigin::kOdometry) {
    if (Status sent = ros_->PublishPose(t, base); !sent.ok()) health_.RecordError(sent.message());
    // The pose of the frame in its cycle (a given start pose has no capture).
    if (origin == PoseOrigin::kFrame && frame_in_cycle_) {
      const auto [times, cycle_start] = *std::exchange(frame_in_cycle_, std::nullopt);
      capture_latency_.Record(times, cycle_start, camera_io::HostNow());
    }
  }
  if (t > latest_odometry_t_) {  // a frame run on extrapolated odometry
    deferred_map_to_odom_.emplace_back(t, base.pose);
    if (deferred_map_to_odom_.size() > 16) deferred_map_to_odom_.pop_front();
    return;
  }
  const Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return;
  if (Status sent = ros_->PublishMapToOdom(t, base.pose, *odom); !sent.ok())
    health_.RecordError(sent.message());
}

void TrackerAgent::PublishDeferredMapToOdom() {
  while (ros_ && !deferred_map_to_odom_.empty() &&
         deferred_map_to_odom_.front().first <= latest_odometry_t_) {
    const auto [t, base] = deferred_map_to_odom_.front();
    deferred_map_to_odom_.pop_front();
    const Result<geometry::Pose2> odom = odometry_.At(t);
    if (!odom.ok()) continue;
    if (Status sent = ros_->PublishMapToOdom(t, base, *odom); !sent.ok())
      health_.RecordError(sent.message());
  }
}

void TrackerAgent::ApplyInitialPose(const transport::RosPoseStamped& given) {
  if (odometry_.empty()) {
    pending_initial_ = given;  // anchored when odometry comes
    return;
  }
  pending_initial_.reset();
  // Anchored to recorded odometry, never to extrapolated; refused when older than the history.
  const InitialPoseAnchor anchor = AnchorInitialPose(given.t, odometry_, latest_odometry_t_);
  if (!anchor.ok) {
    spdlog::warn("initial pose from {} refused: {}", config_.ros.initialpose_topic, anchor.reason);
    return health_.RecordError("initial pose: " + anchor.reason);
  }
  const double t = anchor.t;
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return health_.RecordError("initial pose: " + odom.status().message());
  spdlog::info("initial pose from {}: ({:.4f}, {:.4f}, {:.2f} deg) at t={:.3f}",
               config_.ros.initialpose_topic, given.pose.pose.x, given.pose.pose.y,
               given.pose.pose.theta * 180.0 / M_PI, t);
  initial_ = given.pose;
  WarmUp(t, given.pose);
  tracker_->Reset(given.pose, *odom);
  extrapolated_frame_t_.reset();
  started_ = true, provisional_ = false, coasting_in_a_row_ = 0;
  if (position_update_) position_update_->Forget();
  state_ = tracking::LockState::kCoasting;  // until a frame tracks from it
  health_.RecordLockState(state_);
  propagator_->SetAnchor(t, *odom, given.pose);
  Publish(t, given.pose, state_, PoseOrigin::kGiven);
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
  odometry_ = tracking::OdometryHistory(10.0, extrapolation_s_);
  latest_odometry_t_ = -1e300;
  extrapolated_frame_t_.reset();
  deferred_map_to_odom_.clear();
}

bool TrackerAgent::FrameReady(double t) const {
  if (t <= latest_odometry_t_) return true;
  // Constant-velocity extrapolation needs a velocity: two samples of the current timeline.
  return extrapolation_s_ > 0 && odometry_.size() >= 2 &&
         t - latest_odometry_t_ <= extrapolation_s_;
}

void TrackerAgent::CorrectExtrapolatedOdometry() {
  if (!extrapolated_frame_t_ || *extrapolated_frame_t_ > latest_odometry_t_) return;
  const double t = *std::exchange(extrapolated_frame_t_, std::nullopt);
  const Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) return;
  tracker_->CorrectOdometry(t, *odom);
  propagator_->CorrectAnchorOdometry(t, *odom);
}

std::string TrackerAgent::InOdometryGap(double t) const {
  if (!IsLiveSource(config_.source)) return "";  // recorded runs: as fleetctl track does
  const double gap = odometry_.GapAround(t);
  if (gap <= config_.live.odometry_stale_s) return "";
  return "frame at t=" + std::to_string(t) +
         " captured while odometry had stopped (no sample for " + std::to_string(gap) + " s)";
}

void TrackerAgent::WarmUp(double t, const geometry::PoseWithCovariance& base) {
  if (started_) return;
  spdlog::info("warm-up: asking for the tiles around the start pose ({:.3f}, {:.3f})", base.pose.x,
               base.pose.y);
  Prefetch(t, base.pose);
  ScheduleTrackerWarmUp(base, "start pose");
}

void TrackerAgent::ScheduleTrackerWarmUp(const geometry::PoseWithCovariance& base,
                                         const char* what) {
  // Live only: a replay has no time between events to do it in (its loop decodes no tiles there).
  if (!IsLiveSource(config_.source)) return;
  tracker_warm_up_ = base, warm_up_what_ = what, warm_up_tiles_ = 0, warm_up_ms_ = 0.0;
}

void TrackerAgent::WarmUpTracker() {
  if (!tracker_warm_up_ || loader_->pending() > 0 || loader_->encoded() > 0) return;
  const auto start = std::chrono::steady_clock::now();
  const int normalized = tracker_->WarmUp(*tracker_warm_up_, kTilesNormalizedPerTurn);
  warm_up_tiles_ += normalized;
  warm_up_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (normalized == kTilesNormalizedPerTurn) return;  // more next turn
  tracker_warm_up_.reset();
  spdlog::info("warm-up: {} normalized tiles around the {} ready ({:.1f} ms of work)",
               warm_up_tiles_, warm_up_what_, warm_up_ms_);
}

}  // namespace fleetloc::tracker_agent
