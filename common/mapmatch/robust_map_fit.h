// The robust map fit (issue 16, docs/architecture.md): the mean-shift SE(2) fit of map_fit.h given
// good starts and a check. Starts: the initial correction and the best corrections voted by pairs
// of dense spots whose distance matches a pair of landmarks (pair_votes.h), all within the search
// radius. Each start is refined by the mean-shift fit with h shrinking to the final radius. The
// converged modes are compared by their kernel support at the final radius; the best one must pass
// a validation gate (it lands on enough landmarks, each with enough points, with a residual well
// inside h) and must stand out: a distinct mode supported almost as well makes the fit ambiguous.
// Whatever fails is `converged: false` with the reason and the initial correction — never a
// confident wrong answer. Used by `fleetctl mapmatch`, the global position update and the bench.
#pragma once

#include <Eigen/Core>
#include <span>

#include "base/status.h"
#include "geometry/pose2.h"
#include "mapmatch/map_fit.h"

namespace fleetloc::mapmatch {

struct RobustMapFitOptions {
  // How far the correction may move a point from where `initial` puts it: the kernel radius a
  // user gives (`fleetctl mapmatch --radius`), grown by the final h. h at the start of the fit
  // from `initial` (at least the final h); > 0.
  double search_radius_m = 0.0;
  // h at the end of every fit, of the dense spots, and of the support and validation of a mode;
  // > 0. About three times the points' noise: 0.03 suits corners
  // detected to ~1 cm; noisier points need more (their residuals fail the rms check below).
  double final_radius_m = 0.03;
  // h at which the fit from a voted correction starts (clipped to [final, search radius]): the vote
  // and its fit to the spots already put it within about the final h.
  double voted_start_radius_m = 0.05;
  double shrink_factor = 0.7;        // in (0, 1)
  int max_iterations = 100;          // per start; > 0
  int max_spots = 64;                // > 1
  int max_voted_starts = 8;          // >= 0; 0: only the initial correction (a local fit)
  double min_pair_distance_m = 0.2;  // spots closer than this do not vote; >= 0
  // Validation: the mode lands on at least min_landmarks landmarks, each with at least
  // min_points_per_landmark points within the final h ...
  int min_landmarks = 2;            // >= 2
  int min_points_per_landmark = 3;  // >= 1
  // ... with the rms residual of those pairs at most this share of h: points spread uniformly
  // over the kernel have 0.71, normal noise of σ 0.46 when h = 3σ and 0.64 when h = 1.5σ (noisier
  // points need a larger final h); in (0, 1].
  double max_rms_ratio = 0.65;
  // A distinct valid mode with at least this share of the best one's support: ambiguous; (0, 1].
  double ambiguity_ratio = 0.9;
};

// InvalidInput naming the first option out of range.
Status Validate(const RobustMapFitOptions& options);

// Fits the correction T (as FitMap, map_fit.h) searching within options.search_radius_m of
// `initial`. InvalidInput for bad options or inputs (as CheckMapFitInputs). A fit that cannot be
// trusted is a result: converged false, `reason` saying why, `correction` = `initial`, covariance
// zero, and the statistics (inliers, support, ...) of the best mode examined.
Result<MapFitResult> RobustFitMap(std::span<const Eigen::Vector2d> landmarks,
                                  std::span<const Eigen::Vector2d> points,
                                  std::span<const double> weights, const geometry::Pose2& initial,
                                  const RobustMapFitOptions& options);

}  // namespace fleetloc::mapmatch
