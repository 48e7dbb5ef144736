// Conversions of a vehicle's pose and health to the wire (VehiclePose, VehicleHealth), with the
// fields fleet tools expect: REP-105 pose with covariance and time of validity, VDA 5050
// localized flag, localization score and deviation range, ROS-diagnostics health levels.
#pragma once

#include <string>
#include <vector>

#include "geometry/pose2.h"
#include "tracking/frame_localizer.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::transport {

struct PoseReport {
  std::string vehicle_id;
  double t = 0.0;
  geometry::PoseWithCovariance base_in_map;
  tracking::LockState state = tracking::LockState::kLost;
  long long mosaic_version = 0;
};

fleetloc_VehiclePose ToIdl(const PoseReport& report);
// The report in a received VehiclePose (wire version not checked here).
PoseReport FromIdl(const fleetloc_VehiclePose& pose);

// Localization score in [0, 1] (1: position sigma ≤ 0.1 mm, 0 at 5 mm or not localized) and the
// deviation range (3 sigma of position, metres) of a pose.
double LocalizationScore(const geometry::PoseWithCovariance& pose, tracking::LockState state);
double DeviationRangeM(const geometry::PoseWithCovariance& pose);

fleetloc_LockState ToIdl(tracking::LockState state);
tracking::LockState FromIdl(fleetloc_LockState state);

}  // namespace fleetloc::transport
