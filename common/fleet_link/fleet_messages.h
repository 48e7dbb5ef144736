// Conversions from the wire (VehiclePose, VehicleHealth, ServiceHealth) to the fleet library's
// plain samples, with the checks a receiver owes its peers: wire version, entity id, finite
// numbers. A sample that fails them is rejected with a message naming the sender and the field.
#pragma once

#include <map>
#include <string>

#include "base/status.h"
#include "fleet/vehicle_samples.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::fleet_link {

struct ServiceReport {
  std::string service_id;
  std::string kind;
  fleet::HealthLevel level = fleet::HealthLevel::kOk;
  double t = 0.0;
  std::map<std::string, uint64_t> counters;  // the service's own counters, by name
};

Result<fleet::PoseSample> PoseFromIdl(const fleetloc_VehiclePose& pose);
Result<fleet::HealthSample> HealthFromIdl(const fleetloc_VehicleHealth& health);
Result<ServiceReport> ServiceFromIdl(const fleetloc_ServiceHealth& health);

}  // namespace fleetloc::fleet_link
