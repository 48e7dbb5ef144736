// The fleet as JSON: vehicles, alerts and the summary, as the supervisor's HTTP API and live stream
// and `fleetctl status` print them (field names are the dashboard's and any script's interface;
// times are Unix seconds, lengths metres, angles radians, docs/formats.md).
#pragma once

#include <nlohmann/json.hpp>

#include "fleet/fleet_state.h"

namespace fleetloc::fleet_link {

// One vehicle: newest pose (with the position covariance for the uncertainty ellipse), newest
// health, silence; with `trail`, its recent positions.
nlohmann::json VehicleJson(const fleet::VehicleState& vehicle, bool silent, bool trail);
nlohmann::json AlertJson(const fleet::Alert& alert);
nlohmann::json SummaryJson(const fleet::FleetSummary& summary);

}  // namespace fleetloc::fleet_link
