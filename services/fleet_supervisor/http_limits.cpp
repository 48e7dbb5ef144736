// HTTP limits: range checks.
#include "fleet_supervisor/http_limits.h"

namespace fleetloc::fleet_supervisor {

std::string LimitsProblem(const HttpLimits& l) {
  struct IntRange {
    const char* name;
    int value, min, max;
  };
  for (const IntRange& r :
       {IntRange{"max_connections", l.max_connections, 16, 1 << 20},
        IntRange{"max_connections_per_address", l.max_connections_per_address, 0, 1 << 20},
        IntRange{"max_streams", l.max_streams, 0, 1 << 16}, IntRange{"workers", l.workers, 1, 256},
        IntRange{"queue", l.queue, 1, 1 << 16},
        IntRange{"max_requests_per_connection", l.max_requests_per_connection, 1, 1 << 20},
        IntRange{"max_header_bytes", l.max_header_bytes, 1024, 1 << 20},
        IntRange{"max_header_count", l.max_header_count, 8, 1024},
        IntRange{"max_body_bytes", l.max_body_bytes, 1024, 64 << 20},
        IntRange{"max_ranges", l.max_ranges, 0, 64},
        IntRange{"max_buffered_mb", l.max_buffered_mb, 1, 65536},
        IntRange{"auth_free_failures", l.auth_free_failures, 0, 1000}}) {
    if (r.value < r.min || r.value > r.max) {
      return std::string(r.name) + " must be in [" + std::to_string(r.min) + ", " +
             std::to_string(r.max) + "]";
    }
  }
  struct Range {
    const char* name;
    double value, min, max;
  };
  for (const Range& r : {Range{"header_timeout_s", l.header_timeout_s, 0.1, 300},
                         Range{"keep_alive_timeout_s", l.keep_alive_timeout_s, 0.1, 3600},
                         Range{"write_timeout_s", l.write_timeout_s, 0.1, 3600},
                         Range{"stream_keep_alive_s", l.stream_keep_alive_s, 0.1, 600},
                         Range{"auth_max_backoff_s", l.auth_max_backoff_s, 1, 86400}}) {
    if (!(r.value >= r.min && r.value <= r.max)) {
      return std::string(r.name) + " must be in [" + std::to_string(r.min) + ", " +
             std::to_string(r.max) + "]";
    }
  }
  for (const std::string& host : l.allowed_hosts) {
    if (host.empty() || host.find_first_of(" /\t") != std::string::npos) {
      return "allowed_hosts holds '" + host + "', not a host name or address";
    }
  }
  return "";
}

}  // namespace fleetloc::fleet_supervisor
