// The tracker's own estimate of camera_ground in map (paper 000 §2.2.3, tracking-error
// compensation): advanced by odometry *increments*, never reset to the external absolute pose,
// with covariance growth. Shared by the mosaic tracker and the peer localizers it is compared to.
#pragma once

#include "geometry/pose2.h"
#include "tracking/frame_localizer.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

class InternalEstimate {
 public:
  InternalEstimate(const geometry::Pose2& mount, const OdometryNoiseOptions& noise)
      : mount_(mount), noise_(noise) {}

  // Starts from base_link's pose in map at the time whose odometry pose is `odom`.
  void Reset(const geometry::PoseWithCovariance& base_in_map, const geometry::Pose2& odom);
  // estimate ⊕ (mount⁻¹ ⊕ odom_last⁻¹ ⊕ odom ⊕ mount), covariance grown by the odometry model
  // and, when `odom` was extrapolated `extrapolated_s` past the newest odometry sample, by
  // ExtrapolationCovariance; becomes the estimate and is returned. Requires Reset().
  const geometry::PoseWithCovariance& Predict(double t, const geometry::Pose2& odom,
                                              double extrapolated_s = 0.0);
  // The odometry pose at the last prediction's time `t` became known (it had been extrapolated):
  // the next increment starts from it. Ignored unless t is the last prediction's time.
  void CorrectOdometry(double t, const geometry::Pose2& odom);
  void Correct(const geometry::PoseWithCovariance& camera_in_map) { camera_ = camera_in_map; }

  bool initialized() const { return initialized_; }
  const geometry::PoseWithCovariance& camera() const { return camera_; }
  // Output transform: base_link = camera ⊕ mount⁻¹, with covariance.
  geometry::PoseWithCovariance BaseInMap() const;
  // A frame result carrying BaseInMap() at time t with `state` (other fields left default).
  FrameResult Report(double t, LockState state) const;

 private:
  geometry::Pose2 mount_;
  OdometryNoiseOptions noise_;
  geometry::PoseWithCovariance camera_;
  geometry::Pose2 odom_last_;
  double t_last_ = 0.0;
  bool has_time_ = false;
  bool initialized_ = false;
};

}  // namespace fleetloc::tracking
