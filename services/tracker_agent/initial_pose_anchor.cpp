// Anchoring a start pose to odometry.
#include "tracker_agent/initial_pose_anchor.h"

#include <spdlog/fmt/fmt.h>

namespace fleetloc::tracker_agent {

InitialPoseAnchor AnchorInitialPose(double stamp, const tracking::OdometryHistory& odometry,
                                    double latest_odometry_t) {
  if (odometry.empty()) return {false, 0.0, "no odometry yet"};
  if (stamp == 0.0 || stamp >= latest_odometry_t) return {true, latest_odometry_t, ""};
  if (odometry.At(stamp).ok()) return {true, stamp, ""};
  return {false, 0.0,
          fmt::format("stamped t={:.3f}, before the odometry history (newest sample t={:.3f}): "
                      "the vehicle may have moved since; ignored",
                      stamp, latest_odometry_t)};
}

}  // namespace fleetloc::tracker_agent
