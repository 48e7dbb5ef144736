// VehiclePose conversions and the VDA 5050 quality fields.
#include "transport/pose_messages.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "transport/wire_util.h"

namespace fleetloc::transport {

fleetloc_LockState ToIdl(tracking::LockState state) {
  switch (state) {
    case tracking::LockState::kTracking:
      return fleetloc_LOCK_TRACKING;
    case tracking::LockState::kCoasting:
      return fleetloc_LOCK_COASTING;
    case tracking::LockState::kLost:
      return fleetloc_LOCK_LOST;
    case tracking::LockState::kRelocalized:
      return fleetloc_LOCK_RELOCALIZED;
  }
  return fleetloc_LOCK_LOST;
}

tracking::LockState FromIdl(fleetloc_LockState state) {
  switch (state) {
    case fleetloc_LOCK_TRACKING:
      return tracking::LockState::kTracking;
    case fleetloc_LOCK_COASTING:
      return tracking::LockState::kCoasting;
    case fleetloc_LOCK_RELOCALIZED:
      return tracking::LockState::kRelocalized;
    default:
      return tracking::LockState::kLost;
  }
}

double DeviationRangeM(const geometry::PoseWithCovariance& pose) {
  const Eigen::Matrix2d position = pose.covariance.topLeftCorner<2, 2>();
  const double variance =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(position).eigenvalues().maxCoeff();
  return 3.0 * std::sqrt(std::max(0.0, variance));
}

double LocalizationScore(const geometry::PoseWithCovariance& pose, tracking::LockState state) {
  if (state == tracking::LockState::kLost) return 0.0;
  const double sigma = DeviationRangeM(pose) / 3.0;
  return std::clamp(1.0 - (sigma - 1e-4) / (5e-3 - 1e-4), 0.0, 1.0);
}

fleetloc_VehiclePose ToIdl(const PoseReport& r) {
  fleetloc_VehiclePose pose{};
  pose.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(pose.vehicle_id, r.vehicle_id);
  pose.stamp = ToStamp(r.t);
  pose.x = r.base_in_map.pose.x;
  pose.y = r.base_in_map.pose.y;
  pose.theta = r.base_in_map.pose.theta;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(pose.covariance) =
      r.base_in_map.covariance;
  pose.lock_state = ToIdl(r.state);
  pose.localized = r.state != tracking::LockState::kLost;
  pose.localization_score = static_cast<float>(LocalizationScore(r.base_in_map, r.state));
  pose.deviation_range_m = static_cast<float>(DeviationRangeM(r.base_in_map));
  pose.mosaic_version = r.mosaic_version;
  return pose;
}

PoseReport FromIdl(const fleetloc_VehiclePose& p) {
  PoseReport r;
  r.vehicle_id = GetBounded(p.vehicle_id);
  r.t = ToSeconds(p.stamp);
  r.base_in_map.pose = {p.x, p.y, p.theta};
  r.base_in_map.covariance =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(p.covariance);
  r.state = FromIdl(p.lock_state);
  r.mosaic_version = p.mosaic_version;
  return r;
}

}  // namespace fleetloc::transport
