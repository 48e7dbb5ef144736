// Synthetic map-fit problems like the paper's figure 3: some landmarks of a map observed as
// clusters of noisy points, buried in uniform outliers, all seen through a known wrong pose. Shared
// by the map-fit tests, the fleetctl mapmatch end-to-end test and `fleetctl bench mapfit`.
#pragma once

#include <Eigen/Core>
#include <random>
#include <span>
#include <vector>

#include "geometry/pose2.h"

namespace fleetloc::mapmatch {

struct MapFitProblemOptions {
  int points_per_landmark = 30;   // inliers around each observed landmark
  double noise_sigma_m = 0.05;    // normal noise of an inlier, per axis
  double outlier_fraction = 0.7;  // of all points; in [0, 1)
  double outlier_margin_m =
      1.0;  // outliers are uniform over the observed landmarks' box grown by this
};

struct MapFitProblem {
  std::vector<Eigen::Vector2d> points;  // shuffled; in the drifted frame: truth ⊕ point ≈ landmark
  int inliers = 0;
  geometry::Pose2 truth;  // the correction a perfect fit returns
};

// Observes `landmarks[observed[k]]` through truth⁻¹. Deterministic for a given `rng` state.
MapFitProblem SimulateMapFitProblem(std::span<const Eigen::Vector2d> landmarks,
                                    std::span<const int> observed, const geometry::Pose2& truth,
                                    const MapFitProblemOptions& options, std::mt19937& rng);

// Translation (m) and rotation (rad, absolute) errors of `estimate` against `truth`.
struct CorrectionError {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};
CorrectionError ErrorOf(const geometry::Pose2& estimate, const geometry::Pose2& truth);

}  // namespace fleetloc::mapmatch
