// The fleet supervisor's Prometheus metrics from its fleet picture and counters: vehicles by lock
// state, silent vehicles, open alerts by severity, each vehicle's reported cycle time, tile cache
// hit rate, outbox depth and map-server reachability, and the supervisor's health counters.
// Pure: the supervisor calls it under its fleet lock once per metrics refresh.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fleet/fleet_state.h"
#include "metrics/metric_families.h"

namespace fleetloc::fleet_supervisor {

// Metric names start with this.
inline constexpr const char* kSupervisorMetricPrefix = "fleetloc_supervisor_";

// Adds the fleet's families (vehicles, alerts, per-vehicle health) to `b`.
void AddFleetFamilies(const fleet::FleetState& fleet, metrics::FamilyBuilder* b);

// Adds the supervisor's counters (SupervisorCounters::Snapshot) and whether a map server reports.
void AddSupervisorFamilies(const std::vector<std::pair<std::string, uint64_t>>& counters,
                           bool map_server_alive, metrics::FamilyBuilder* b);

}  // namespace fleetloc::fleet_supervisor
