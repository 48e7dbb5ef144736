// Time-indexed odometry history (paper 000 §2.2.2, delay compensation): odometry poses are kept
// with their own timestamps and interpolated at a camera frame's capture time.
#pragma once

#include <deque>

#include "base/status.h"
#include "geometry/camera_model.h"

namespace fleetloc::tracking {

class OdometryHistory {
 public:
  // Keeps at most `max_age_s` of history behind the newest sample; extrapolates at most
  // `max_extrapolation_s` past it under constant linear and angular velocity.
  explicit OdometryHistory(double max_age_s = 10.0, double max_extrapolation_s = 0.1);

  // Appends a sample. Rejects non-finite values and times not after the last sample, leaving
  // the history unchanged.
  Status Add(const geometry::StampedPose& sample);

  // Pose at time t: interpolated (x, y linear; theta along the shorter arc) between samples, or
  // extrapolated a little past the newest. NotFound when t is outside what the history covers.
  Result<geometry::Pose2> At(double t) const;

  // How far apart the two samples around time t are (0 when t is not between two samples): a
  // pose interpolated across a long gap (odometry that stopped) is only a guess.
  double GapAround(double t) const;

  bool empty() const { return samples_.empty(); }
  size_t size() const { return samples_.size(); }

 private:
  std::deque<geometry::StampedPose> samples_;
  double max_age_s_;
  double max_extrapolation_s_;
};

// Pose at fraction s ∈ [0, 1] from a to b (theta along the shorter arc).
geometry::Pose2 Interpolate(const geometry::Pose2& a, const geometry::Pose2& b, double s);

}  // namespace fleetloc::tracking
