// Global position update from a window of detected floor points (see global_position_update.h).
#include "mapmatch/global_position_update.h"

#include <cmath>
#include <string>

namespace fleetloc::mapmatch {
namespace {

Status CheckUpdateInputs(const DetectionWindow& window, double now_s,
                         const geometry::PoseWithCovariance& current,
                         const GlobalPositionUpdateOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  if (window.empty()) return InvalidInput("global position update: the detection window is empty");
  if (!(now_s >= window.newest_t_s()))
    return InvalidInput("global position update: time " + std::to_string(now_s) +
                        " is before the newest detection");
  if (!current.pose.ToVector().allFinite() || !current.covariance.allFinite())
    return InvalidInput("global position update: the current pose is not finite");
  return Status::Ok();
}

}  // namespace

DetectionWindow::DetectionWindow(double length_s) : length_s_(length_s) {
  FLEETLOC_CHECK(std::isfinite(length_s) && length_s > 0.0);
}

Status DetectionWindow::Add(double t_s, const geometry::Pose2& estimated_pose,
                            std::span<const Eigen::Vector2d> vehicle_points) {
  if (!std::isfinite(t_s)) return InvalidInput("detection window: the time is not finite");
  if (t_s < newest_t_s())
    return InvalidInput("detection window: time " + std::to_string(t_s) +
                        " is before the newest detection " + std::to_string(newest_t_s()));
  if (!estimated_pose.ToVector().allFinite())
    return InvalidInput("detection window: the pose at time " + std::to_string(t_s) +
                        " is not finite");
  for (std::size_t i = 0; i < vehicle_points.size(); ++i) {
    if (!vehicle_points[i].allFinite())
      return InvalidInput("detection window: point " + std::to_string(i) + " at time " +
                          std::to_string(t_s) + " is not finite");
  }
  for (const Eigen::Vector2d& p : vehicle_points) points_.push_back({t_s, estimated_pose * p});
  DropOlderThanWindow(t_s);
  return Status::Ok();
}

void DetectionWindow::DropOlderThanWindow(double now_s) {
  while (!points_.empty() && points_.front().t_s < now_s - length_s_) points_.pop_front();
}

void DetectionWindow::ApplyCorrection(const geometry::Pose2& correction) {
  for (Detection& d : points_) d.map_xy = correction * d.map_xy;
}

std::vector<Eigen::Vector2d> DetectionWindow::MapPoints() const {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(points_.size());
  for (const Detection& d : points_) xy.push_back(d.map_xy);
  return xy;
}

std::vector<double> DetectionWindow::Weights(double now_s, double half_life_s) const {
  std::vector<double> weights;
  weights.reserve(points_.size());
  for (const Detection& d : points_)
    weights.push_back(half_life_s > 0 ? std::exp2(-(now_s - d.t_s) / half_life_s) : 1.0);
  return weights;
}

Status Validate(const GlobalPositionUpdateOptions& options) {
  if (!(std::isfinite(options.weight_half_life_s) && options.weight_half_life_s >= 0.0))
    return InvalidInput("global position update: weight_half_life_s must be >= 0");
  return Validate(options.fit);
}

Result<PositionUpdate> UpdateGlobalPosition(const DetectionWindow& window, double now_s,
                                            std::span<const Eigen::Vector2d> landmarks,
                                            const geometry::PoseWithCovariance& current,
                                            const GlobalPositionUpdateOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(CheckUpdateInputs(window, now_s, current, options));
  const std::vector<Eigen::Vector2d> points = window.MapPoints();
  PositionUpdate update;
  update.pose = current;
  const std::vector<double> weights = window.Weights(now_s, options.weight_half_life_s);
  Result<MapFitResult> fit = RobustFitMap(landmarks, points, weights, {}, options.fit);
  if (!fit.ok()) return fit.status();
  update.fit = std::move(*fit);
  if (!update.fit.converged) return update;
  update.applied = true;
  update.pose =
      geometry::ComposeFixed({update.fit.correction, update.fit.covariance}, current.pose);
  return update;
}

}  // namespace fleetloc::mapmatch
