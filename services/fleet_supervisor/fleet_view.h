// The JSON the HTTP API and the live stream serve (field names are the dashboard's and any
// script's interface; times are Unix seconds, lengths metres, angles radians, docs/formats.md).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fleet/fleet_state.h"
#include "fleet_supervisor/history_store.h"
#include "transport/remap_client.h"

namespace fleetloc::fleet_supervisor {

// One vehicle: newest pose (with the position covariance for the uncertainty ellipse), newest
// health, silence; with `trail`, its recent positions.
nlohmann::json VehicleJson(const fleet::VehicleState& vehicle, bool silent, bool trail);
nlohmann::json AlertJson(const fleet::Alert& alert);
nlohmann::json SummaryJson(const fleet::FleetSummary& summary);
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

// History series as column arrays over the supervisor's receive time ("t"), thinned to at most `max_points` per plotted quantity with
// fleet::DecimateMinMax (poses by deviation range; health by cycle p95 and by inliers).
nlohmann::json PoseHistoryJson(const std::vector<StoredPose>& poses, size_t max_points);
nlohmann::json HealthHistoryJson(const std::vector<StoredHealth>& health, size_t max_points);

}  // namespace fleetloc::fleet_supervisor
