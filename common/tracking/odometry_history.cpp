// Odometry history with interpolation and short constant-velocity extrapolation.
#include "tracking/odometry_history.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fleetloc::tracking {

using geometry::Pose2;
using geometry::StampedPose;
using geometry::WrapAngle;

Pose2 Interpolate(const Pose2& a, const Pose2& b, double s) {
  return {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y),
          WrapAngle(a.theta + s * WrapAngle(b.theta - a.theta))};
}

OdometryHistory::OdometryHistory(double max_age_s, double max_extrapolation_s)
    : max_age_s_(max_age_s), max_extrapolation_s_(max_extrapolation_s) {}

Status OdometryHistory::Add(const StampedPose& s) {
  if (!std::isfinite(s.t) || !std::isfinite(s.pose.x) || !std::isfinite(s.pose.y) ||
      !std::isfinite(s.pose.theta)) {
    return InvalidInput("odometry sample is not finite");
  }
  if (!samples_.empty() && s.t <= samples_.back().t) {
    std::ostringstream m;
    m.precision(17);
    m << "odometry time " << s.t << " is not after the previous sample " << samples_.back().t;
    return InvalidInput(m.str());
  }
  samples_.push_back({s.t, {s.pose.x, s.pose.y, WrapAngle(s.pose.theta)}});
  while (samples_.size() > 2 && samples_.front().t < s.t - max_age_s_) samples_.pop_front();
  return Status::Ok();
}

Result<Pose2> OdometryHistory::At(double t) const {
  if (samples_.empty() || !std::isfinite(t) || t < samples_.front().t) {
    return NotFound("no odometry at time " + std::to_string(t));
  }
  const StampedPose& last = samples_.back();
  if (t >= last.t) {
    if (t - last.t > max_extrapolation_s_) {
      return NotFound("odometry ends " + std::to_string(t - last.t) + " s before time " +
                      std::to_string(t));
    }
    if (samples_.size() < 2 || t == last.t) return last.pose;
    const StampedPose& prev = samples_[samples_.size() - 2];
    // Constant linear and angular velocity over the last interval (paper 000 §2).
    const Pose2 step = geometry::Between(prev.pose, last.pose);
    const double s = (t - last.t) / (last.t - prev.t);
    return last.pose * Interpolate(Pose2{}, step, s);
  }
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t,
                                      [](double v, const StampedPose& p) { return v < p.t; });
  const StampedPose& b = *after;
  const StampedPose& a = *(after - 1);
  return Interpolate(a.pose, b.pose, (t - a.t) / (b.t - a.t));
}

double OdometryHistory::GapAround(double t) const {
  if (samples_.size() < 2 || !(t > samples_.front().t) || !(t < samples_.back().t)) return 0.0;
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t,
                                      [](double v, const StampedPose& p) { return v < p.t; });
  return after->t - (after - 1)->t;
}

}  // namespace fleetloc::tracking
