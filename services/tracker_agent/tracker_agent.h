// The tracker agent of one vehicle: tracks its camera over the shared mosaic streamed from the map
// server (tiles on demand and prefetched along the motion, cached with a byte bound, dropped when
// a TileUpdate announces a new version), publishes VehiclePose at the odometry rate (the last
// tracked pose propagated with odometry, and the tracked pose itself at each frame's time) and
// VehicleHealth periodically. Frames wait until odometry covers their time (delay compensation),
// so the replayed results equal `fleetctl track` over the same run; a live frame a little past the
// newest odometry runs at once on extrapolated odometry (live.odometry_extrapolation_s). Without
// an initial pose, and when lock is lost, it relocalizes globally with the map server's place
// index; a relocalized pose is provisional until the next frame tracks from it. With a forward
// camera and a landmark map, the global position update corrects the pose whenever the downward
// camera is not tracking (or the run has no downward frames at all: the initial pose propagated
// with odometry and corrected).
//
// Three parts, pumped by Run: the localization core (no DDS: localization_core.h), the DDS link
// (dds_link.h) and the patch collector (patch_collector.h).
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>

#include "metrics/metrics_exporter.h"
#include "run_io/run.h"
#include "tracker_agent/agent_config.h"
#include "tracker_agent/agent_health.h"
#include "tracker_agent/agent_position_update.h"
#include "tracker_agent/dds_link.h"
#include "tracker_agent/localization_core.h"
#include "tracker_agent/patch_collector.h"
#include "tracker_agent/vehicle_input.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracker_agent {

// The localization core's options from the agent's configuration.
LocalizationOptions LocalizationOptionsFor(const AgentConfig& config);

class TrackerAgent {
 public:
  // Joins the DDS domain, waits (up to mosaic_wait_s) for a map server's MosaicInfo and sets up
  // the tracker for `camera`, starting from `initial` (base_link in map at the first frame), or,
  // without one, from the first frame the place index relocalizes. `position_update` (may be
  // null: none) takes the forward camera's images.
  static Result<std::unique_ptr<TrackerAgent>> Create(
      const AgentConfig& config, const run_io::CameraFile& camera,
      const std::optional<geometry::PoseWithCovariance>& initial,
      const tracking::TrackerOptions& options,
      std::unique_ptr<AgentPositionUpdate> position_update = nullptr);

  // Runs until the input ends or `stop` is set.
  Status Run(VehicleInput& input, const std::atomic<bool>& stop);
  const AgentHealth& health() const { return health_; }

 private:
  explicit TrackerAgent(const AgentConfig& config)
      : config_(config), health_(config.live.issue_hold_s) {}
  // One input event to the localization core.
  void HandleEvent(const InputEvent& event);
  // After each event: tile updates, reachability, tile decoding and warm-up, the place index,
  // patches, and health and metrics when due.
  void PumpBetweenEvents();
  void PublishHealth();
  void RefreshMetrics();
  Status WriteSummary();  // frames, cycle times, tiles, relocalization

  AgentConfig config_;
  AgentHealth health_;
  std::unique_ptr<DdsLink> link_;
  std::unique_ptr<LocalizationCore> core_;
  std::unique_ptr<PatchCollector> patches_;
  // Prometheus /metrics (config "metrics", off by default): refreshed from the loop.
  std::unique_ptr<metrics::ServiceMetrics> metrics_;
  std::chrono::steady_clock::time_point next_health_;
  VehicleInput* input_ = nullptr;  // while running: for its issues
};

}  // namespace fleetloc::tracker_agent
