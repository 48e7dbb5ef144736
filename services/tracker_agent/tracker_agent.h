// The tracker agent of one vehicle: tracks its camera over the shared mosaic streamed from the map
// server (tiles on demand and prefetched along the motion, cached with a byte bound, dropped when
// a TileUpdate announces a new version), publishes VehiclePose at the odometry rate (the last
// tracked pose propagated with odometry, and the tracked pose itself at each frame's time) and
// VehicleHealth periodically. Frames wait until odometry covers their time (delay compensation),
// so the replayed results equal `fleetctl track` over the same run; a live frame a little past the
// newest odometry runs at once on extrapolated odometry (live.odometry_extrapolation_s). Without an initial pose, and when
// lock is lost, it relocalizes globally with the map server's place index; a relocalized pose is
// provisional until the next frame tracks from it. With a forward camera and a landmark map, the
// global position update corrects the pose whenever the downward camera is not tracking (or the
// run has no downward frames at all: the initial pose propagated with odometry and corrected).
#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <set>

#include "calibration/rectifier.h"
#include "io/run.h"
#include "mosaic/mosaic_view.h"
#include "tracker_agent/agent_config.h"
#include "metrics/histogram.h"
#include "metrics/metrics_exporter.h"
#include "tracker_agent/agent_health.h"
#include "tracker_agent/capture_latency.h"
#include "tracker_agent/agent_position_update.h"
#include "tracker_agent/agent_relocalizer.h"
#include "tracker_agent/patch_outbox.h"
#include "tracker_agent/ros_bridge.h"
#include "tracker_agent/vehicle_input.h"
#include "tracking/mosaic_tracker.h"
#include "tracking/odometry_history.h"
#include "tracking/pose_propagator.h"
#include "transport/dds_tile_loader.h"
#include "transport/patch_client.h"
#include "transport/pose_messages.h"
#include "tracker_agent/map_server_directory.h"
#include "transport/tile_client.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::tracker_agent {

class TrackerAgent {
 public:
  // Joins the DDS domain, waits (up to mosaic_wait_s) for a map server's MosaicInfo and sets up
  // the tracker for `camera`, starting from `initial` (base_link in map at the first frame), or,
  // without one, from the first frame the place index relocalizes. `position_update` (may be
  // null: none) takes the forward camera's images.
  static Result<std::unique_ptr<TrackerAgent>> Create(
      const AgentConfig& config, const io::CameraFile& camera,
      const std::optional<geometry::PoseWithCovariance>& initial,
      const tracking::TrackerOptions& options,
      std::unique_ptr<AgentPositionUpdate> position_update = nullptr);

  // Runs until the input ends or `stop` is set.
  Status Run(VehicleInput& input, const std::atomic<bool>& stop);
  const AgentHealth& health() const { return health_; }

 private:
  TrackerAgent(const AgentConfig& config, const io::CameraFile& camera,
               const std::optional<geometry::PoseWithCovariance>& initial);
  Status Open(const tracking::TrackerOptions& options);
  void OnOdometry(double t, const geometry::Pose2& odom);
  // The odometry source began a new timeline: the history is dropped and the pose the vehicle had
  // at the end of the old one anchors the first sample of the new one.
  void OnOdometryRestart();
  // A start pose from the vehicle's stack (ROS initialpose, base_link in map at its stamp):
  // the tracker restarts there, anchored to the odometry at the stamp (or the latest, when the
  // stamp is zero or not covered yet); refused when stamped before the odometry history (the
  // vehicle may have moved since: AnchorInitialPose). Kept until odometry arrives when there is none.
  void ApplyInitialPose(const transport::RosPoseStamped& given);
  void ProcessReadyFrames();
  // A waiting frame can run: odometry covers its time, or (live sources) it is at most
  // live.odometry_extrapolation_s past the newest sample, which is then extrapolated.
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
  // live.odometry_stale_s): its odometry would be a guess; the reason to drop it, else empty.
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
  void Track(double t, const cv::Mat& frame, const FrameTimes& times = {});
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
  Status WriteSummary() const;  // frames, cycle times, tiles, relocalization
  // Asks ahead for the tiles of the footprint now (frame time t) and along the predicted motion.
  void Prefetch(double t, const geometry::Pose2& base);
  void AddFootprintTiles(const geometry::Pose2& base, std::set<mosaic::TileKey>* keys) const;
  // Decodes at most `max_tiles` of the prefetched tiles that arrived (~1.5 ms each). Live sources:
  // kTilesDecodedPerTurn between events, so that no frame's cycle decodes a burst of them.
  void DecodeArrivedTiles(size_t max_tiles);
  static constexpr size_t kTilesDecodedPerTurn = 2;
  void ApplyTileUpdates();
  // Where a published pose comes from. The ROS 2 pose topic carries the poses at frame times and
  // given start poses, the map → odom transform all three; only a frame's pose has a capture time
  // to time the capture → pose latency from.
  enum class PoseOrigin { kFrame, kOdometry, kGiven };
  void Publish(double t, const geometry::PoseWithCovariance& base, tracking::LockState state,
               PoseOrigin origin = PoseOrigin::kFrame);
  void PublishRos(double t, const geometry::PoseWithCovariance& base, PoseOrigin origin);
  // Until every tile of the mosaic has a map server announcing it, or `deadline`.
  void WaitForTileCoverage(std::chrono::steady_clock::time_point deadline);
  // A vehicle that starts without a pose can do nothing before the place index is loaded: waits
  // for it (at most mosaic_wait_s) so that its first frames are relocalized, not dropped.
  void WaitForPlaceIndex();
  // A map server is reachable when it reads our tile requests (DDS match) and was heard from
  // (ServiceHealth) within map_server_timeout_s; the tile loader stops waiting for the tiles of
  // one that is not. map_server_reachable_: every owning server is.
  void UpdateMapServerReachability();
  void PublishHealth();
  void RefreshMetrics();
  // Queues the frame as a patch when it shows floor the mosaic does not (rate-limited).
  void MaybeCollectPatch(double t, const cv::Mat& frame, const tracking::FrameResult& result);
  // One acknowledgement (DecideAck): counts it for its replica, or drops a rejected patch.
  void TakeAck(const transport::ReceivedAck& ack);
  // Takes acknowledgements and (re)sends what is due.
  void PumpPatches();
  // At the end of the input: keeps pumping until the outbox is empty or drain_s passed.
  void DrainPatches(const std::atomic<bool>& stop);

  AgentConfig config_;
  io::CameraFile camera_;
  std::optional<geometry::PoseWithCovariance> initial_;
  std::unique_ptr<transport::Participant> participant_;
  std::unique_ptr<transport::TileClient> tiles_;
  std::unique_ptr<transport::DdsTileLoader> loader_;
  std::unique_ptr<transport::PatchClient> patches_;
  std::unique_ptr<MapServerDirectory> map_servers_;
  std::unique_ptr<PatchOutbox> outbox_;
  double last_patch_t_ = -1e300;
  std::unique_ptr<transport::Topic<fleetloc_VehiclePose>> pose_topic_;
  std::unique_ptr<transport::Topic<fleetloc_VehicleHealth>> health_topic_;
  std::unique_ptr<transport::Topic<fleetloc_TileUpdate>> update_topic_;
  std::unique_ptr<transport::VehicleStreamWriter<fleetloc_VehiclePose>> pose_writer_;
  std::unique_ptr<transport::VehicleStreamWriter<fleetloc_VehicleHealth>> health_writer_;
  std::unique_ptr<transport::Reader<fleetloc_TileUpdate>> update_reader_;
  mosaic::MosaicLayout layout_;
  std::shared_ptr<mosaic::TileCache> tile_cache_;
  std::unique_ptr<mosaic::MosaicView> view_;
  std::unique_ptr<tracking::MosaicTracker> tracker_;
  std::optional<calibration::Rectifier> rectifier_;
  std::unique_ptr<AgentRelocalizer> relocalizer_;
  bool provisional_ = false;  // the pose came from relocalization and no frame tracked from it yet
  int coasting_in_a_row_ = 0;
  double last_relocalize_t_ = -1e300;
  // Live sources extrapolate up to live.odometry_extrapolation_s past the newest sample; replay
  // and simulation never do (frames wait until odometry covers them).
  double extrapolation_s_ = 0.0;
  tracking::OdometryHistory odometry_{10.0, 0.0};
  std::optional<geometry::PoseWithCovariance> tracker_warm_up_;  // where WarmUpTracker works
  int warm_up_tiles_ = 0;
  double warm_up_ms_ = 0.0;
  const char* warm_up_what_ = "start pose";
  std::optional<double> extrapolated_frame_t_;  // the last frame run on extrapolated odometry
  std::deque<std::pair<double, geometry::Pose2>> deferred_map_to_odom_;  // base_link in map at t
  long long extrapolated_frames_ = 0;
  double max_extrapolated_s_ = 0.0;
  std::optional<tracking::PosePropagator> propagator_;
  tracking::LockState state_ = tracking::LockState::kLost;
  std::unique_ptr<AgentPositionUpdate> position_update_;
  struct WaitingFrame {
    double t = 0.0;
    bool forward = false;  // a forward-camera image (else a rectified downward frame)
    cv::Mat image;
    FrameTimes times;      // live sources: for the capture -> pose latency
  };
  std::deque<WaitingFrame> waiting_frames_;  // until odometry covers their time, in time order
  double latest_odometry_t_ = -1e300;
  bool started_ = false;
  bool map_server_reachable_ = true;
  AgentHealth health_;
  // Prometheus /metrics (config "metrics", off by default): refreshed from the loop.
  metrics::Histogram cycle_seconds_{metrics::Histogram::LatencyBoundsS()};
  metrics::Histogram tile_round_trip_{metrics::Histogram::LatencyBoundsS()};
  std::unique_ptr<metrics::ServiceMetrics> metrics_;
  // Live vehicles: the ROS 2 bridge, the input (for its issues) and capture → pose-on-the-wire
  // latencies (host clock; the last 10,000 frames).
  std::unique_ptr<RosBridge> ros_;
  VehicleInput* input_ = nullptr;
  std::optional<transport::RosPoseStamped> pending_initial_;
  std::optional<geometry::PoseWithCovariance> restart_pose_;
  CaptureLatency capture_latency_;  // live sources' frame poses
  // The frame in its cycle now, and when the cycle began (host clock): timed when its pose is out.
  std::optional<std::pair<FrameTimes, double>> frame_in_cycle_;
};

}  // namespace fleetloc::tracker_agent
