// When a start pose from the vehicle's stack (ROS initialpose: base_link in map at its stamp) can
// be anchored to odometry, and at which odometry time.
#pragma once

#include <string>

#include "tracking/odometry_history.h"

namespace fleetloc::tracker_agent {

struct InitialPoseAnchor {
  bool ok = false;
  double t = 0.0;      // the odometry time the pose is anchored at (when ok)
  std::string reason;  // why it cannot be anchored (when not ok)
};

// A stamp covered by recorded odometry (never extrapolated: up to `latest_odometry_t`) is anchored
// there; a zero stamp ("now", as RViz sends) or one after the newest sample at the newest sample.
// A stamp older than the history cannot be anchored: the vehicle may have moved since (a start
// pose delivered late to an agent that joined late would be placed where the vehicle was at the
// stamp but at the time of the newest odometry), so it is refused.
InitialPoseAnchor AnchorInitialPose(double stamp, const tracking::OdometryHistory& odometry,
                                    double latest_odometry_t);

}  // namespace fleetloc::tracker_agent
