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
};

Status Validate(const AgentConfig& config);

// Reads `path` over the defaults. NotFound / InvalidInput "<file>: field '<name>': <what>".
Result<AgentConfig> LoadAgentConfig(const std::string& path);

}  // namespace fleetloc::tracker_agent
