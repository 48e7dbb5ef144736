// Wheel-odometry simulation: base_link in odom integrated from the true motion increments with
// distance and turn scale errors, a gyro-like heading drift and white noise.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/camera_model.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

// `truth` is base_link in map at strictly ascending times. Returns base_link in odom at the same
// times: odom starts at options.start_pose (or at truth's first pose), and each true increment
// (dx, dy, dtheta) over dt becomes
//   (dx, dy) · (1 + distance_scale_error) + white noise along travel (variance σd² · distance),
//   dtheta · (1 + heading_scale_error) + heading_drift_rad_s · dt + white noise (variance σh² ·
//   dt).
// Deterministic for a seed.
std::vector<geometry::StampedPose> SimulateOdometry(const std::vector<geometry::StampedPose>& truth,
                                                    const OdometryOptions& options,
                                                    std::uint64_t seed);

}  // namespace fleetloc::sim
