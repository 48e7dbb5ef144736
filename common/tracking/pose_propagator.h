// base_link in map at any odometry time after the last tracked frame (docs/architecture.md step 8:
// the agent propagates the frame's pose to "now" with odometry when it publishes): the frame's pose
// ⊕ the odometry increment since, with covariance grown by the odometry noise model.
#pragma once

#include "geometry/pose2.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

class PosePropagator {
 public:
  explicit PosePropagator(OdometryNoiseOptions noise) : noise_(noise) {}

  // The pose at time t, whose odometry pose was `odom`.
  void SetAnchor(double t, const geometry::Pose2& odom, const geometry::PoseWithCovariance& base);
  // The anchor's odometry pose, extrapolated when it was set, is now known: later poses propagate
  // from it. Ignored unless `t` is the anchor's time.
  void CorrectAnchorOdometry(double t, const geometry::Pose2& odom);
  bool anchored() const { return anchored_; }
  double anchor_time() const { return t_; }
  // Requires anchored(). At the anchor's own odometry pose it returns the anchor unchanged.
  geometry::PoseWithCovariance At(double t, const geometry::Pose2& odom) const;

 private:
  OdometryNoiseOptions noise_;
  bool anchored_ = false;
  double t_ = 0.0;
  geometry::Pose2 odom_;
  geometry::PoseWithCovariance base_;
};

}  // namespace fleetloc::tracking
