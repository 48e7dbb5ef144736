// Where and how a service serves Prometheus /metrics: the "metrics" object of its JSON
// configuration (unknown keys rejected, every field range-checked with a message naming it).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "base/status.h"
#include "io/json_fields.h"

namespace fleetloc::metrics {

struct MetricsOptions {
  bool enabled = false;
  std::string bind = "127.0.0.1";  // loopback only unless configured otherwise
  int port = 0;                    // 0: any free port (logged and written to port_file)
  std::string port_file;           // if set, the bound port is written there
  int threads = 1;                 // scrapes served at once (1-4); more wait in the accept queue
  double request_timeout_s = 2.0;  // a client that has not sent its request by then is cut off
  double refresh_period_s = 1.0;   // the service refreshes what a scrape returns this often
};

// `service` names the config in messages ("map server config").
Status Validate(const MetricsOptions& options, const std::string& service);

// Reads the object member "metrics" of `fields` (whose JSON is `parent`) over `*options`.
// InvalidInput "<file>: field 'metrics.<key>': <what>" for an unknown key or a bad value.
Status ReadMetricsOptions(const io::JsonFields& fields, const nlohmann::json& parent,
                          MetricsOptions* options);

}  // namespace fleetloc::metrics
