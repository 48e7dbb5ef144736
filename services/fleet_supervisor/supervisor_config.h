// The fleet supervisor's configuration: typed options with defaults, read from a JSON file
// (unknown keys rejected, every field range-checked with a message naming it).
#pragma once

#include <string>

#include "base/status.h"
#include "fleet/fleet_state.h"
#include "fleet_supervisor/http_limits.h"
#include "fleet_supervisor/vda5050_options.h"
#include "metrics/metrics_options.h"

namespace fleetloc::fleet_supervisor {

struct SupervisorConfig {
  std::string supervisor_id = "sup-1";  // 1-11 of [A-Za-z0-9_-]; names its tile partition
  int domain_id = 0;
  std::string dds_config_path;          // empty: CYCLONEDDS_URI or the compiled-in loopback
  std::string http_bind = "127.0.0.1";  // loopback only unless configured otherwise
  int http_port = 8080;                 // 0: any free port (logged and written to port_file)
  std::string port_file;                // if set, the bound port is written there
  // Re-mapping and every other change need this token (Authorization: Bearer <token>); empty
  // (and no file): the dashboard is read-only. The file's first line is the token; the file must
  // not be readable by group or others, and a token has 16-1024 printable characters.
  std::string maintainer_token;
  std::string maintainer_token_file;
  std::string history_db = "fleet_history.db";
  double retention_s = 7 * 86400.0;    // older history rows are deleted
  double history_period_s = 1.0;       // at most one stored pose per vehicle per period
  double max_query_range_s = 86400.0;  // a longer history query is refused (400)
  int max_history_points = 5000;       // per series in one answer
  double stream_period_s = 0.1;        // live stream snapshots at most this often
  std::string web_dir;                 // empty: found beside the binary or in the source tree
  // The dashboard's map and chart libraries, Debian's libjs-leaflet and libjs-chart.js, served at
  // /vendor/leaflet/ and /vendor/chart.js/ from here.
  std::string js_dir = "/usr/share/javascript";
  std::string mosaic_name;  // shown with the version on the dashboard; empty: "floor"
  int tile_cache_mb = 32;
  int min_tile_level = 0;  // overview tiles below this level are refused
  double tile_timeout_s = 3.0;
  double health_period_s = 1.0;  // the supervisor's own ServiceHealth
  fleet::AlertOptions alerts;
  fleet::TrailOptions trail;
  HttpLimits http;  // connection, stream, head and auth limits ("http")
  // Prometheus /metrics on a port of its own ("metrics"; on by default at 127.0.0.1:9472).
  metrics::MetricsOptions metrics = DefaultMetrics();
  // VDA 5050 visualization over MQTT for a fleet manager ("vda5050"; off by default).
  Vda5050Options vda5050;

  static metrics::MetricsOptions DefaultMetrics() {
    metrics::MetricsOptions m;
    m.enabled = true;
    m.port = 9472;
    return m;
  }
};

Status Validate(const SupervisorConfig& config);

// Reads `path` over the defaults. NotFound / InvalidInput "<file>: field '<name>': <what>".
Result<SupervisorConfig> LoadSupervisorConfig(const std::string& path);

// The token in force: `maintainer_token`, else the first line of `maintainer_token_file` (NotFound
// naming the file if it cannot be read; InvalidInput naming it when group or others may read it),
// else empty (read-only). InvalidInput for a token shorter than 16 or longer than 1024
// characters, or with a character that is not printable ASCII.
Result<std::string> ResolveMaintainerToken(const SupervisorConfig& config);

}  // namespace fleetloc::fleet_supervisor
