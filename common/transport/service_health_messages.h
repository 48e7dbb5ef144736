// A service's health report (ServiceHealth: level, at most one named issue, every counter) filled
// and written in one place, for the map server and the fleet supervisor.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "transport/typed_io.h"

namespace fleetloc::transport {

struct ServiceHealthReport {
  std::string service_id;
  std::string kind;  // "map_server", "fleet_supervisor", ...
  struct Issue {
    std::string name;
    fleetloc_HealthLevel level = fleetloc_HEALTH_WARN;
    std::string message;
  };
  std::optional<Issue> issue;                                   // none: the service is OK
  std::vector<std::pair<std::string, std::uint64_t>> counters;  // at most 64 are sent
};

// Writes the report stamped now; the level is the issue's, or OK without one.
Status WriteServiceHealth(const Writer<fleetloc_ServiceHealth>& writer,
                          const ServiceHealthReport& report);

}  // namespace fleetloc::transport
