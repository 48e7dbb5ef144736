// Odometry propagation of the last tracked pose.
#include "tracking/pose_propagator.h"

#include <algorithm>

#include "base/status.h"
#include "tracking/motion_model.h"

namespace fleetloc::tracking {

void PosePropagator::SetAnchor(double t, const geometry::Pose2& odom,
                               const geometry::PoseWithCovariance& base) {
  anchored_ = true, t_ = t, odom_ = odom, base_ = base;
}

void PosePropagator::CorrectAnchorOdometry(double t, const geometry::Pose2& odom) {
  if (anchored_ && t == t_) odom_ = odom;
}

geometry::PoseWithCovariance PosePropagator::At(double t, const geometry::Pose2& odom) const {
  FLEETLOC_CHECK(anchored_);
  return Predict(base_, odom_.Inverse() * odom, std::max(0.0, t - t_), noise_);
}

}  // namespace fleetloc::tracking
