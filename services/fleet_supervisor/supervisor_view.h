// The supervisor's own JSON views: readiness (GET /readyz), re-mapping jobs and history series.
// The fleet itself (vehicles, alerts, summary) is fleet_link/fleet_view.h, shared with fleetctl.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fleet_supervisor/history_store.h"
#include "transport/remap_client.h"

namespace fleetloc::fleet_supervisor {

// One readiness condition of the supervisor (GET /readyz): its name, whether it holds, and why not.
struct ReadinessCheck {
  std::string name;
  bool ok = false;
  std::string detail;
};
// {"ready": all checks hold, "checks": {name: {"ok", "detail"}}}; *ready is set to the same.
nlohmann::json ReadinessJson(const std::vector<ReadinessCheck>& checks, bool* ready);

// A re-mapping job; the 64-bit command id as a string (JavaScript numbers hold 53 bits).
nlohmann::json RemapJobJson(const transport::RemapProgress& job);

// History series as column arrays over the supervisor's receive time ("t"), thinned to at most
// `max_points` per plotted quantity with fleet::DecimateMinMax (poses by deviation range; health by
// cycle p95 and by inliers).
nlohmann::json PoseHistoryJson(const std::vector<StoredPose>& poses, size_t max_points);
nlohmann::json HealthHistoryJson(const std::vector<StoredHealth>& health, size_t max_points);

}  // namespace fleetloc::fleet_supervisor
