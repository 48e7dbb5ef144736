// The map fits fleetloc's mean-shift fit (mapmatch/map_fit.h) is benchmarked against: RANSAC over
// nearest-landmark pairs (cv::estimateAffinePartial2D; "RANSAC-NN" in the bench) and plain
// point-to-point ICP. Both pair each point with its nearest landmark under the current correction
// and return the same result type. The correspondence-free RANSAC is pair_ransac_map_fit.h.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "geometry/pose2.h"
#include "mapmatch/map_fit.h"

namespace fleetloc::peers {

struct NearestRansacOptions {
  double inlier_threshold_m = 0.03;  // reprojection distance of an inlier pair
  int max_iterations = 2000;
  double confidence = 0.995;
  int refine_iterations = 10;  // Levenberg–Marquardt on the inliers
};

// Pairs every point (moved by `initial`) with its nearest landmark and fits a similarity by
// RANSAC (in coordinates centred on the points); the rotation and translation of that similarity,
// composed with `initial`, are the correction (its scale, ideally 1, is dropped). `converged` false
// when OpenCV finds no model. Requires non-empty, finite inputs.
mapmatch::MapFitResult NearestRansacMapFit(std::span<const Eigen::Vector2d> landmarks,
                                           std::span<const Eigen::Vector2d> points,
                                           const geometry::Pose2& initial,
                                           const NearestRansacOptions& options = {});

// The rigid transform that best moves `from` onto `to` (same size, >= 2) in least squares, in
// closed form (2-D Procrustes). Used by ICP and by the correspondence-free RANSAC's refinement.
geometry::Pose2 RigidFit(const std::vector<Eigen::Vector2d>& from,
                         const std::vector<Eigen::Vector2d>& to);

struct IcpMapFitOptions {
  int max_iterations = 50;
  double translation_tolerance_m = 1e-7;  // converged when a step is shorter than both
  double rotation_tolerance_rad = 1e-8;
};

// Plain ICP: pair every point with its nearest landmark under the current correction, solve the
// closed-form rigid fit of all pairs, repeat until the step vanishes. No outlier rejection.
mapmatch::MapFitResult IcpMapFit(std::span<const Eigen::Vector2d> landmarks,
                                 std::span<const Eigen::Vector2d> points,
                                 const geometry::Pose2& initial,
                                 const IcpMapFitOptions& options = {});

}  // namespace fleetloc::peers
