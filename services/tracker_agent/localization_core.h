// The tracker agent's localization, without DDS: frames wait in time order until odometry covers
// them (or, live, until it can be extrapolated to them), then the mosaic tracker runs; between
// frames the last tracked pose is propagated with odometry. Lost or coasting too long, a frame is
// relocalized globally; a relocalized pose is provisional until the next frame tracks from it.
// Forward-camera images correct the pose when the downward camera is not tracking. Tiles,
// relocalization and where the poses go are ports (localization_ports.h).
#pragma once

#include <deque>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "calibration/rectifier.h"
#include "metrics/histogram.h"
#include "mosaic/raster_source.h"
#include "run_io/run.h"
#include "tracker_agent/agent_position_update.h"
#include "tracker_agent/health_counters.h"
#include "tracker_agent/localization_ports.h"
#include "tracking/mosaic_tracker.h"
#include "tracking/odometry_history.h"
#include "tracking/pose_propagator.h"

namespace fleetloc::tracker_agent {

struct LocalizationOptions {
  // A live source (camera and ROS 2 odometry): frames may run on extrapolated odometry, a frame
  // captured while odometry had stopped is dropped, and the tracker warms up between events.
  bool live = false;
  double odometry_extrapolation_s = 0.0;  // live: how far past the newest sample a frame may be
  double odometry_stale_s = 0.5;          // live: odometry gap around a frame that drops it
  bool relocalize_on_lost = true;
  int relocalize_after_coasting_frames = 5;
  double relocalize_interval_s = 0.5;  // frame time between two attempts
  int prefetch_margin_px = 256;        // tiles this far around the predicted footprint are asked
  double prefetch_ahead_s = 0.5;       // ... along the motion predicted this far ahead
  std::string initial_pose_source = "initialpose";  // where given start poses come from (logs)
};

// What the core needs from the agent; every pointer must outlive the core.
struct LocalizationPorts {
  TileSupply* tiles = nullptr;
  GlobalRelocalization* relocalization = nullptr;
  PosePublisher* poses = nullptr;
  TrackedFrameObserver* tracked_frames = nullptr;
  HealthCounters* health = nullptr;
};

// Frames run on odometry extrapolated past its newest sample (live sources).
struct ExtrapolationStats {
  long long frames = 0;
  double max_s = 0.0;
  double horizon_s = 0.0;
};

class LocalizationCore {
 public:
  // Tracks `camera` over `mosaic` (laid out as `layout`), starting from `initial` (base_link in
  // map at the first frame) or, without one, from the first frame relocalized. `position_update`
  // (may be null: none) takes the forward camera's images.
  LocalizationCore(const LocalizationOptions& options, const tracking::TrackerOptions& tracker,
                   const run_io::CameraFile& camera, const mosaic::MosaicLayout& layout,
                   mosaic::RasterSource* mosaic,
                   const std::optional<geometry::PoseWithCovariance>& initial,
                   const LocalizationPorts& ports,
                   std::unique_ptr<AgentPositionUpdate> position_update);

  void OnOdometry(double t, const geometry::Pose2& odom);
  // The odometry source began a new timeline: the history is dropped and the pose the vehicle had
  // at the end of the old one anchors the first sample of the new one.
  void OnOdometryRestart();
  // A start pose from the vehicle's stack (base_link in map at `stamp`): the tracker restarts
  // there, anchored to the odometry at the stamp (or the latest, when the stamp is zero or not
  // covered yet); refused when stamped before the odometry history (the vehicle may have moved
  // since: AnchorInitialPose). Kept until odometry arrives when there is none.
  void ApplyInitialPose(double stamp, const geometry::PoseWithCovariance& pose);
  // A downward camera frame (rectified here if the camera needs it), queued until it can run.
  void AddDownwardFrame(double t, const cv::Mat& raw, const FrameTimes& times);
  // A forward-camera image (not rectified: its detector has its own camera model); ignored
  // without a position update.
  void AddForwardImage(double t, const cv::Mat& image);
  // Before the first event: asks for the tiles around the initial pose, if there is one.
  void WarmUpAtStart();
  // Between events: live sources decode a few arrived tiles, and the tracker warms up.
  void BetweenEvents();
  // A new mosaic version changed these tiles: the tracker forgets what it made of them.
  void DropTiles(const std::vector<mosaic::TileKey>& changed);

  tracking::LockState lock_state() const { return state_; }
  const AgentPositionUpdate* position_update() const { return position_update_.get(); }
  const metrics::Histogram& cycle_seconds() const { return cycle_seconds_; }
  ExtrapolationStats extrapolation() const {
    return {extrapolated_frames_, max_extrapolated_s_, extrapolation_s_};
  }

 private:
  void ProcessReadyFrames();
  // A waiting frame can run: odometry covers its time, or (live sources) it is at most
  // odometry_extrapolation_s past the newest sample, which is then extrapolated.
  bool FrameReady(double t) const;
  // How far past the newest odometry sample frame time t is (0 when covered).
  double ExtrapolatedSpan(double t) const { return std::max(0.0, t - latest_odometry_t_); }
  // Once odometry covers the last frame that ran on extrapolated odometry: the tracker and the
  // propagator continue from the odometry pose at its time instead of the extrapolated one.
  void CorrectExtrapolatedOdometry();
  // map -> odom of the frame poses published before odometry covered their time, sent once it
  // does (with the odometry then, not the extrapolated one: map -> odom -> base_link is the pose).
  void PublishDeferredMapToOdom();
  // A live frame captured while odometry had stopped (the samples around it farther apart than
  // odometry_stale_s): its odometry would be a guess; the reason to drop it, else empty.
  std::string InOdometryGap(double t) const;
  // Before the first frame: asks for the tiles around the start pose; once they are in,
  // WarmUpTracker normalizes them (no fetch, decoding or normalization in the first frame's cycle).
  void WarmUp(double t, const geometry::PoseWithCovariance& base);
  // Live sources: has WarmUpTracker prepare the tracker at `base` (the start pose, or a
  // relocalized pose, whose tiles were asked for), named `what` in its log lines.
  void ScheduleTrackerWarmUp(const geometry::PoseWithCovariance& base, const char* what);
  // Between events: the tracker's first-use work at the start pose (normalized tiles,
  // kTilesNormalizedPerTurn at a time, ~1.4 ms each), once its tiles arrived and were decoded
  // (nothing in flight or encoded); dropped when a frame runs first.
  void WarmUpTracker();
  static constexpr int kTilesNormalizedPerTurn = 2;
  void Track(double t, const cv::Mat& frame, const FrameTimes& times);
  // Before the first frame of either camera: the tracker and the propagator start from the initial
  // pose (false without one: the first downward frame is to relocalize).
  bool Start(double t, const geometry::Pose2& odom);
  // A forward-camera image: its landmarks into the window; when a fit is due and the downward
  // camera is not tracking, the corrected pose restarts the tracker and is published.
  void UpdatePosition(double t, const cv::Mat& image);
  // After a frame's result: lost, or coasting for too long, asks for relocalization.
  bool NeedsRelocalization(const tracking::FrameResult& result) const;
  // Relocalizes the frame (at most once per relocalize_interval_s of frame time); on success
  // restarts the tracker there and publishes the pose as `relocalized`. True on success.
  bool TryRelocalize(double t, const cv::Mat& frame, const geometry::Pose2& odom);
  // Asks ahead for the tiles of the footprint now (frame time t) and along the predicted motion.
  void Prefetch(double t, const geometry::Pose2& base);
  void AddFootprintTiles(const geometry::Pose2& base, std::set<mosaic::TileKey>* keys) const;
  // Decodes at most `max_tiles` of the prefetched tiles that arrived (~1.5 ms each). Live sources:
  // kTilesDecodedPerTurn between events, so that no frame's cycle decodes a burst of them.
  void DecodeArrivedTiles(size_t max_tiles);
  static constexpr size_t kTilesDecodedPerTurn = 2;
  // Out to the pose publisher, with map -> odom when it wants it and the pose is not lost.
  void Publish(double t, const geometry::PoseWithCovariance& base, tracking::LockState state,
               PoseOrigin origin = PoseOrigin::kFrame);
  void PublishMapToOdom(double t, const geometry::Pose2& base);

  LocalizationOptions options_;
  run_io::CameraFile camera_;
  mosaic::MosaicLayout layout_;
  std::optional<geometry::PoseWithCovariance> initial_;
  LocalizationPorts ports_;
  HealthCounters& health_;
  tracking::MosaicTracker tracker_;
  tracking::PosePropagator propagator_;
  std::optional<calibration::Rectifier> rectifier_;
  std::unique_ptr<AgentPositionUpdate> position_update_;
  bool started_ = false;
  bool provisional_ = false;  // the pose came from relocalization and no frame tracked from it yet
  int coasting_in_a_row_ = 0;
  double last_relocalize_t_ = -1e300;
  tracking::LockState state_ = tracking::LockState::kLost;
  // Live sources extrapolate up to odometry_extrapolation_s past the newest sample; replay
  // and simulation never do (frames wait until odometry covers them).
  double extrapolation_s_ = 0.0;
  tracking::OdometryHistory odometry_{10.0, 0.0};
  double latest_odometry_t_ = -1e300;
  std::optional<double> extrapolated_frame_t_;  // the last frame run on extrapolated odometry
  long long extrapolated_frames_ = 0;
  double max_extrapolated_s_ = 0.0;
  std::deque<std::pair<double, geometry::Pose2>> deferred_map_to_odom_;  // base_link in map at t
  struct WaitingFrame {
    double t = 0.0;
    bool forward = false;  // a forward-camera image (else a rectified downward frame)
    cv::Mat image;
    FrameTimes times;  // live sources: for the capture -> pose latency
  };
  std::deque<WaitingFrame> waiting_frames_;  // until odometry covers their time, in time order
  std::optional<std::pair<double, geometry::PoseWithCovariance>> pending_initial_;  // stamp, pose
  std::optional<geometry::PoseWithCovariance> restart_pose_;
  std::optional<geometry::PoseWithCovariance> tracker_warm_up_;  // where WarmUpTracker works
  int warm_up_tiles_ = 0;
  double warm_up_ms_ = 0.0;
  const char* warm_up_what_ = "start pose";
  // The frame in its cycle now, when the cycle began (host clock): timed when its pose is out.
  std::optional<FrameCycle> frame_in_cycle_;
  metrics::Histogram cycle_seconds_{metrics::Histogram::LatencyBoundsS()};
};

}  // namespace fleetloc::tracker_agent
