// LocalizationCore's frames: the queue, the tracker's cycle, relocalization when lock is lost,
// the forward camera's position updates, and the poses they publish.
#include "tracker_agent/localization_core.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "camera_io/camera_source.h"
#include "rectification/camera_rectifier.h"

namespace fleetloc::tracker_agent {

LocalizationCore::LocalizationCore(const LocalizationOptions& options,
                                   const tracking::TrackerOptions& tracker,
                                   const run_io::CameraFile& camera,
                                   const mosaic::MosaicLayout& layout, mosaic::RasterSource* mosaic,
                                   const std::optional<geometry::PoseWithCovariance>& initial,
                                   const LocalizationPorts& ports,
                                   std::unique_ptr<AgentPositionUpdate> position_update)
    : options_(options),
      camera_(camera),
      layout_(layout),
      initial_(initial),
      ports_(ports),
      health_(*ports.health),
      tracker_(tracker, camera.model, mosaic),
      propagator_(tracker.odometry),
      rectifier_(rectification::RectifierFor(camera)),
      position_update_(std::move(position_update)),
      extrapolation_s_(options.live ? options.odometry_extrapolation_s : 0.0),
      odometry_(10.0, extrapolation_s_) {}

void LocalizationCore::AddDownwardFrame(double t, const cv::Mat& raw, const FrameTimes& times) {
  const cv::Mat image = rectifier_ ? rectifier_->Rectify(raw) : raw;
  waiting_frames_.push_back({t, false, image, times});
  ProcessReadyFrames();
}

void LocalizationCore::AddForwardImage(double t, const cv::Mat& image) {
  if (!position_update_) return;
  waiting_frames_.push_back({t, true, image, {t, 0.0, 0.0}});
  ProcessReadyFrames();
}

void LocalizationCore::Publish(double t, const geometry::PoseWithCovariance& base,
                               tracking::LockState state, PoseOrigin origin) {
  const std::optional<FrameCycle> cycle =
      origin == PoseOrigin::kFrame ? frame_in_cycle_ : std::nullopt;
  ports_.poses->PublishPose({t, base, state, origin, cycle});
  if (state != tracking::LockState::kLost && ports_.poses->WantsMapToOdom()) {
    PublishMapToOdom(t, base.pose);
  }
}

void LocalizationCore::ProcessReadyFrames() {
  while (!waiting_frames_.empty() && FrameReady(waiting_frames_.front().t)) {
    const WaitingFrame frame = std::move(waiting_frames_.front());
    waiting_frames_.pop_front();
    const double span = ExtrapolatedSpan(frame.t);
    extrapolated_frame_t_ = span > 0 ? std::optional<double>(frame.t) : std::nullopt;
    if (span > 0) {
      ++extrapolated_frames_;
      max_extrapolated_s_ = std::max(max_extrapolated_s_, span);
    }
    if (const std::string gap = InOdometryGap(frame.t); !gap.empty()) {
      spdlog::warn("dropped: {}", gap);
      health_.RecordDroppedFrame(gap);
    } else if (frame.forward) {
      UpdatePosition(frame.t, frame.image);
    } else {
      Track(frame.t, frame.image, frame.times);
    }
  }
}

bool LocalizationCore::Start(double t, const geometry::Pose2& odom) {
  if (!initial_) return false;
  tracker_.Reset(*initial_, odom);
  started_ = true;
  propagator_.SetAnchor(t, odom, *initial_);
  return true;
}

void LocalizationCore::UpdatePosition(double t, const cv::Mat& image) {
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) {
    return health_.RecordDroppedFrame("forward image at t=" + std::to_string(t) + ": " +
                                      odom.status().message());
  }
  if (!started_) {
    if (!Start(t, *odom)) return;  // nowhere to place its landmarks until a frame relocalizes
    state_ = tracking::LockState::kCoasting;  // odometry only, until a frame or a fit
    health_.RecordLockState(state_);
    Publish(t, *initial_, state_, PoseOrigin::kGiven);
  }
  const geometry::PoseWithCovariance estimate = propagator_.At(t, *odom);
  if (Status added = position_update_->AddImage(t, image, estimate.pose); !added.ok()) {
    return health_.RecordDroppedFrame(added.message());
  }
  // The mosaic tracks to millimetres, the map fit to centimetres: a tracked pose stays.
  const bool use = state_ != tracking::LockState::kTracking;
  const std::optional<geometry::PoseWithCovariance> corrected =
      position_update_->Update(t, estimate, use);
  if (!corrected || !use) return;
  tracker_.Reset(*corrected, *odom);  // the next frame tracks from the corrected pose
  state_ = tracking::LockState::kRelocalized;
  health_.RecordLockState(state_);
  propagator_.SetAnchor(t, *odom, *corrected);
  Publish(t, *corrected, state_);
}

void LocalizationCore::Track(double t, const cv::Mat& frame, const FrameTimes& times) {
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) {
    health_.RecordDroppedFrame("frame at t=" + std::to_string(t) + ": " + odom.status().message());
    return;
  }
  if (!started_ && !Start(t, *odom)) {  // where the vehicle is is unknown until a frame relocalizes
    (void)TryRelocalize(t, frame, *odom);
    return;
  }
  if (std::exchange(tracker_warm_up_, std::nullopt)) {
    spdlog::info(
        "warm-up: a frame came before the tiles around the {} were ready ({} "
        "normalized); it does the rest in its cycle",
        warm_up_what_, warm_up_tiles_);
  }
  // Ask for the predicted footprint's missing tiles in one batch before the tracker needs them
  // (one round trip instead of one per tile it reads).
  Prefetch(t, propagator_.At(t, *odom).pose);
  // What the loop did not decode yet (a replay runs its frames back to back; live, normally
  // nothing): before the cycle, as the tiles asked for ahead always were.
  DecodeArrivedTiles(std::numeric_limits<size_t>::max());
  if (options_.live) frame_in_cycle_ = FrameCycle{times, camera_io::HostNow()};
  const auto start = std::chrono::steady_clock::now();
  tracking::FrameResult result = tracker_.Track(frame, t, *odom, ExtrapolatedSpan(t));
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (std::exchange(provisional_, false) && result.state != tracking::LockState::kTracking) {
    spdlog::warn("the relocalized pose did not hold at t={:.3f}: lost again", t);
    result.state = tracking::LockState::kLost;
  }
  coasting_in_a_row_ = result.state == tracking::LockState::kCoasting ? coasting_in_a_row_ + 1 : 0;
  if (result.state == tracking::LockState::kTracking) ports_.relocalization->ResetTrajectory();
  health_.RecordFrame(result, ms);
  cycle_seconds_.Observe(ms / 1000.0);
  state_ = result.state;
  if (NeedsRelocalization(result) && TryRelocalize(t, frame, *odom)) {
    frame_in_cycle_.reset();  // published there (timed if it was)
    return;
  }
  propagator_.SetAnchor(t, *odom, result.base_in_map);
  Publish(t, result.base_in_map, result.state);
  frame_in_cycle_.reset();  // a lost pose is not timed
  Prefetch(t, result.base_in_map.pose);
  ports_.tracked_frames->FrameTracked(t, frame, result);
}

bool LocalizationCore::NeedsRelocalization(const tracking::FrameResult& result) const {
  if (!options_.relocalize_on_lost) return false;
  return result.state == tracking::LockState::kLost ||
         coasting_in_a_row_ >= options_.relocalize_after_coasting_frames;
}

bool LocalizationCore::TryRelocalize(double t, const cv::Mat& frame, const geometry::Pose2& odom) {
  GlobalRelocalization& relocalization = *ports_.relocalization;
  if (!relocalization.ready() || t - last_relocalize_t_ < options_.relocalize_interval_s)
    return false;
  last_relocalize_t_ = t;
  Result<relocalization::Relocalization> found = relocalization.Relocalize(frame, odom);
  if (!found.ok()) {
    health_.RecordError("relocalization: " + found.status().message());
    return false;
  }
  health_.RecordRelocalization(found->found);
  if (!found->found) {
    spdlog::info("relocalization at t={:.3f} found nothing ({:.0f} ms): {}", t,
                 relocalization.last_ms(), found->reason);
    return false;
  }
  const geometry::PoseWithCovariance& base = found->base_in_map;
  spdlog::info(
      "relocalized at t={:.3f}: ({:.4f}, {:.4f}, {:.2f} deg), {} inliers, {} frame(s), "
      "{:.0f} ms",
      t, base.pose.x, base.pose.y, base.pose.theta * 180.0 / M_PI, found->inliers,
      found->from_trajectory ? found->trajectory_frames : 1, relocalization.last_ms());
  tracker_.Reset(base, odom);
  started_ = true;
  provisional_ = true;
  coasting_in_a_row_ = 0;
  if (position_update_) position_update_->Forget();  // its points were placed before the jump
  state_ = tracking::LockState::kRelocalized;
  propagator_.SetAnchor(t, odom, base);
  Publish(t, base, state_);
  Prefetch(t, base.pose);
  ScheduleTrackerWarmUp(base, "relocalized pose");  // the next frame tracks from it
  return true;
}

}  // namespace fleetloc::tracker_agent
