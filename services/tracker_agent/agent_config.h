// The tracker agent's configuration: typed options with defaults, from a JSON file (unknown keys
// rejected, each field range-checked with a message naming it), overridable from the command line.
#pragma once

#include <string>

#include "base/status.h"
#include "metrics/metrics_options.h"
#include "tracker_agent/live_config.h"

namespace fleetloc::tracker_agent {

struct AgentConfig {
  std::string vehicle_id = "agv-1";  // 1-11 of [A-Za-z0-9_-]
  int domain_id = 0;
  std::string dds_config_path;  // empty: CYCLONEDDS_URI or the compiled-in loopback
  // "replay" (a recorded run), "sim" (a live simulated vehicle), or a live vehicle's camera:
  // "aravis" (GenICam) or "gstreamer" (a pipeline), with ROS 2 odometry
  // (docs/vehicle_integration.md)
  std::string source = "replay";
  std::string run_path;  // replay source: a run directory (docs/formats.md)
  // sim source: a vehicle driving forever over a floor image (origin at (0, height · resolution)).
  std::string sim_floor;  // the floor image (the map server's mosaic is imported from it)
  double sim_resolution_m = 0.0005;
  double sim_speed_px_s = 3000.0;
  double sim_rate_hz = 5.0;
  double sim_start_fraction = 0.0;  // where on the route this vehicle starts (0..1)
  int sim_seed = 1;
  bool paced = true;                 // at recorded / real-time speed (else as fast as possible)
  std::string tracker_options_path;  // tracker options JSON (empty: defaults)
  int tile_cache_mb = 64;            // raw mosaic tiles kept (LRU, byte-bounded)
  int tile_timeout_ms = 2000;        // one wait for a missing tile
  int prefetch_margin_px = 256;   // tiles this far around the predicted footprint are asked ahead
  double prefetch_ahead_s = 0.5;  // ... along the motion predicted this far ahead (odometry)
  double health_period_s = 1.0;
  // The map server counts as unreachable when none of its health reports (1 Hz by default) came
  // for this long; the agent then tracks from its cache and says so in its health.
  double map_server_timeout_s = 3.0;
  double mosaic_wait_s = 30.0;  // how long to wait for a map server at start
  // Patches of floor that looks different from the mosaic, kept in an outbox until acknowledged.
  std::string outbox_path;  // empty: fleetloc-outbox-<vehicle_id>.db in the working dir
  // The outbox holds at most this many patches and megabytes; beyond, the oldest tenth's lowest
  // quality patch goes (counted, reported in the vehicle's health).
  int outbox_max_patches = 500;
  int outbox_max_mb = 256;
  double patch_min_interval_s = 2.0;  // at most one patch per this many seconds
  double patch_min_changed = 0.3;     // share of the frame's blocks that must look different
  double patch_retry_s = 2.0;         // resend an unacknowledged patch after this long
  double drain_s = 10.0;              // at the end of the input, wait this long for acks
  std::string summary_path;           // if set: a JSON summary (frames, cycle times) at exit
  // Global relocalization with the place index the map server publishes.
  std::string start_pose = "given";  // "given" (the run's or simulator's) or "relocalize" (none)
  bool relocalize_on_lost = true;    // when lock is lost ("kidnapped vehicle")
  int relocalize_after_coasting_frames = 5;  // also after this many frames in a row without a fix
  double relocalize_interval_s = 0.5;        // frame time between two attempts
  // Attempts whose single frame finds nothing are combined with odometry, up to this many within
  // 1 m of travel (multi-frame relocalization, issue 17; 1: single frames only).
  int relocalize_trajectory_frames = 3;
  // The dense place searches' heading pairs run on this many cores (1 or 2): a lost vehicle's
  // tracker is idle, so both cores of a 2-core vehicle CPU search. On an idle 2-core machine the
  // attempts' p95 fell by 35–40 % on 320×240 plain concrete (docs/benchmarks.md, session 46); on
  // one whose other core is busy, 2 was slower (session 32): set 1 where other work shares the CPU.
  int relocalize_threads = 2;
  // Global position update (docs/architecture.md, docs/forward_camera.md): landmarks the forward
  // camera sees (a run's forward/) fitted to the landmark map; it corrects the pose when the
  // downward camera is not tracking.
  std::string landmarks_path;             // landmarks.csv (docs/formats.md); empty: the run's own
                                          // landmarks.csv if it has one
  double position_update_period_s = 1.0;  // one map fit per this much forward-camera time
  double position_update_window_s = 2.0;  // ... over the detections of this last stretch
  double position_update_half_life_s = 1.0;  // older detections count less (0: all alike)
  LiveOptions live;                          // "camera", "live", "aravis", "gstreamer"
  RosOptions ros;                            // "ros": on by default for the live sources
  // Prometheus /metrics ("metrics"; off by default; port 9473 when enabled without one).
  metrics::MetricsOptions metrics = DefaultMetrics();

  static metrics::MetricsOptions DefaultMetrics() {
    metrics::MetricsOptions m;
    m.port = 9473;
    return m;
  }
};

Status Validate(const AgentConfig& config);
bool IsLiveSource(const std::string& source);  // aravis or gstreamer

// Reads `path` over the defaults. NotFound / InvalidInput "<file>: field '<name>': <what>".
Result<AgentConfig> LoadAgentConfig(const std::string& path);

}  // namespace fleetloc::tracker_agent
