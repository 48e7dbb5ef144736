// The tracker agent's configuration: typed options with defaults, from a JSON file (unknown keys
// rejected, each field range-checked with a message naming it), overridable from the command line.
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::tracker_agent {

struct AgentConfig {
  std::string vehicle_id = "agv-1";   // 1-11 of [A-Za-z0-9_-]
  int domain_id = 0;
  std::string dds_config_path;        // empty: CYCLONEDDS_URI or the compiled-in loopback
  std::string run_path;               // replay source: a run directory (CONTRACT §4)
  bool paced = true;                  // replay at recorded speed (else as fast as possible)
  std::string tracker_options_path;   // tracker options JSON (empty: defaults)
  int tile_cache_mb = 64;             // raw mosaic tiles kept (LRU, byte-bounded)
  int tile_timeout_ms = 2000;         // one wait for a missing tile
  int prefetch_margin_px = 256;       // tiles this far around the predicted footprint are asked ahead
  double health_period_s = 1.0;
  double mosaic_wait_s = 30.0;        // how long to wait for a map server at start
  // Patches of floor that looks different from the mosaic, kept in an outbox until acknowledged.
  std::string outbox_path;            // empty: fleetloc-outbox-<vehicle_id>.db in the working dir
  double patch_min_interval_s = 2.0;  // at most one patch per this many seconds
  double patch_min_changed = 0.15;    // share of the frame's blocks that must look different
  double patch_retry_s = 2.0;         // resend an unacknowledged patch after this long
  double drain_s = 10.0;              // at the end of the input, wait this long for acks
  std::string summary_path;           // if set: a JSON summary (frames, cycle times) at exit
};

Status Validate(const AgentConfig& config);

// Reads `path` over the defaults. NotFound / InvalidInput "<file>: field '<name>': <what>".
Result<AgentConfig> LoadAgentConfig(const std::string& path);

}  // namespace fleetloc::tracker_agent
