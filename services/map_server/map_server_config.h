// The map server's configuration: typed options with defaults, read from a JSON file (unknown keys
// rejected, every field range-checked with a message naming it).
#pragma once

#include <optional>
#include <string>

#include "base/status.h"
#include "map_server/resource_config.h"
#include "metrics/metrics_options.h"
#include "mosaic/tile_ownership.h"
#include "mosaic_upkeep/remap_job.h"

namespace fleetloc::map_server {

struct MapServerConfig {
  std::string server_id = "map-1";  // 1-11 of [A-Za-z0-9_-]
  std::string mosaic_path;          // the SQLite mosaic this server owns (required)
  int domain_id = 0;
  std::string dds_config_path;  // empty: CYCLONEDDS_URI or the compiled-in loopback
  std::optional<mosaic::TileOwnership> owned_tiles;  // level-0 tile range; absent: every tile
  int max_tiles_per_request = 256;
  int max_patch_bytes = 4 << 20;  // encoded patch image; larger ones are rejected
  int max_patch_side_px = 4096;
  // Each vehicle's rate and quotas, the decoding queue ("patch_intake"; its limits are the two
  // above).
  PatchIntake intake;
  // Old tile versions and patches deleted, and how often ("retention").
  Retention retention;
  int max_vehicles = 4096;  // reply channels kept open (LRU)
  int tile_cache_mb = 64;   // encoded tiles kept in memory
  double health_period_s = 1.0;
  // Build (or load from the mosaic file) and publish the place index of each version served, so
  // vehicles can relocalize anywhere (global relocalization).
  bool serve_place_index = true;
  // After each index: the floor's self-similarity on a grid × grid of frame-sized places (0: not
  // checked); places with a twin are logged and reported in the health (self_similar_floor).
  int self_similarity_grid = 3;
  // How re-mapping jobs judge patches and when a vehicle is quarantined ("patch_admission").
  mosaic_upkeep::RemapPolicy remap_policy;
  // Prometheus /metrics on a port of its own ("metrics"; on by default at 127.0.0.1:9471).
  metrics::MetricsOptions metrics = DefaultMetrics();

  static metrics::MetricsOptions DefaultMetrics() {
    metrics::MetricsOptions m;
    m.enabled = true;
    m.port = 9471;
    return m;
  }
};

Status Validate(const MapServerConfig& config);

// Reads `path` over the defaults. NotFound / InvalidInput "<file>: field '<name>': <what>".
Result<MapServerConfig> LoadMapServerConfig(const std::string& path);

}  // namespace fleetloc::map_server
