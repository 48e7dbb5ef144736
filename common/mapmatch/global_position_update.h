// Global position update (paper 001 §5, docs/architecture.md): floor points detected over a short
// time window, in which odometry is still good, are placed in the map frame with the
// odometry-propagated pose estimate at their detection time; the robust map fit (robust_map_fit.h)
// of those points against the landmark map, searching within its search radius of the estimate,
// gives the correction T of the estimate, and the vehicle pose becomes T ⊕ pose — only when the fit
// passed its validation.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <span>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"
#include "mapmatch/robust_map_fit.h"

namespace fleetloc::mapmatch {

// The points detected during the last `length_s` seconds, each placed in the map frame with the
// pose estimate at its detection time.
class DetectionWindow {
 public:
  // Requires a finite length_s > 0 (checked: aborts otherwise — a configuration bug).
  explicit DetectionWindow(double length_s);

  // Adds the points detected at `t_s`, given in the vehicle frame, placed with `estimated_pose`
  // (the odometry-propagated estimate at t_s), and drops points older than t_s − length_s.
  // InvalidInput (nothing added) for a non-finite time, pose or point, or a time before the newest.
  Status Add(double t_s, const geometry::Pose2& estimated_pose,
             std::span<const Eigen::Vector2d> vehicle_points);
  // Drops the points detected before now_s − length_s.
  void DropOlderThanWindow(double now_s);
  // After the pose estimate was corrected by T (pose ← T ⊕ pose), moves the stored points the same
  // way, so they agree with the estimates that follow.
  void ApplyCorrection(const geometry::Pose2& correction);

  std::vector<Eigen::Vector2d> MapPoints() const;
  // One weight per point, 0.5^(age / half_life_s) with age = now_s − t; all 1 when half_life_s = 0.
  std::vector<double> Weights(double now_s, double half_life_s) const;
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  double newest_t_s() const { return points_.empty() ? -INFINITY : points_.back().t_s; }

 private:
  struct Detection {
    double t_s = 0.0;
    Eigen::Vector2d map_xy = Eigen::Vector2d::Zero();
  };
  double length_s_;
  std::deque<Detection> points_;  // by time
};

struct GlobalPositionUpdateOptions {
  double weight_half_life_s = 0.0;  // older points count less; >= 0, 0: all points count alike
  // The estimate may be up to 0.5 m off at the points; detections smeared over the window by
  // odometry drift call for a final h of 0.1 m.
  RobustMapFitOptions fit{.search_radius_m = 0.5, .final_radius_m = 0.1};
};

// InvalidInput naming the first option out of range.
Status Validate(const GlobalPositionUpdateOptions& options);

struct PositionUpdate {
  // false: the fit did not converge or failed its validation (fit.reason; fit.ambiguous when
  // another correction was supported alike) and `pose` is unchanged
  bool applied = false;
  // T ⊕ current, its covariance that of T carried to the pose (first order): the fit is an
  // absolute measurement, so it replaces the drifted uncertainty instead of adding to it.
  geometry::PoseWithCovariance pose;
  MapFitResult fit;
};

// Fits the window's points (weighted by age at now_s) against the landmarks and applies the
// correction to `current`. InvalidInput for bad options, an empty window, a time before the newest
// point, a non-finite pose or a bad landmark map (as RobustFitMap).
Result<PositionUpdate> UpdateGlobalPosition(const DetectionWindow& window, double now_s,
                                            std::span<const Eigen::Vector2d> landmarks,
                                            const geometry::PoseWithCovariance& current,
                                            const GlobalPositionUpdateOptions& options);

}  // namespace fleetloc::mapmatch
