// Odometry-increment prediction of the tracker's own camera estimate.
#include "tracking/internal_estimate.h"

#include <cmath>

#include "base/status.h"
#include "tracking/motion_model.h"

namespace fleetloc::tracking {

void InternalEstimate::Reset(const geometry::PoseWithCovariance& base_in_map,
                             const geometry::Pose2& odom) {
  camera_ = geometry::ComposeFixed(base_in_map, mount_);
  odom_last_ = odom;
  has_time_ = false;
  initialized_ = true;
}

const geometry::PoseWithCovariance& InternalEstimate::Predict(double t, const geometry::Pose2& odom,
                                                              double extrapolated_s) {
  FLEETLOC_CHECK(initialized_);
  const double dt_s = has_time_ ? t - t_last_ : 0.0;
  // The camera moves by mount⁻¹ ⊕ increment ⊕ mount in its own frame.
  geometry::PoseWithCovariance increment = CameraIncrement(odom_last_, odom, dt_s, mount_, noise_);
  increment.covariance +=
      ExtrapolationCovariance(extrapolated_s, std::hypot(mount_.x, mount_.y), noise_);
  camera_ = geometry::Compose(camera_, increment);
  odom_last_ = odom;
  t_last_ = t;
  has_time_ = true;
  return camera_;
}

void InternalEstimate::CorrectOdometry(double t, const geometry::Pose2& odom) {
  if (has_time_ && t == t_last_) odom_last_ = odom;
}

geometry::PoseWithCovariance InternalEstimate::BaseInMap() const {
  return geometry::ComposeFixed(camera_, mount_.Inverse());
}

FrameResult InternalEstimate::Report(double t, LockState state) const {
  FrameResult result;
  result.t = t;
  result.base_in_map = BaseInMap();
  result.state = state;
  return result;
}

}  // namespace fleetloc::tracking
