// Mean-shift mode search (paper 001, docs/architecture.md): with the Epanechnikov kernel of radius
// h the mode estimate moves to the (weighted) mean of the points within h of it, until it stops
// moving. It finds the densest cluster near the start even when most points are outliers. Used for
// single points (paper figure 2) and for clustering relocalization votes.
#pragma once

#include <Eigen/Core>
#include <span>

#include "base/status.h"

namespace fleetloc::mapmatch {

struct MeanShiftOptions {
  double radius = 0.0;       // h, in the points' unit; > 0
  int max_iterations = 100;  // > 0
  double tolerance = 1e-9;   // stop when a step is shorter than tolerance × radius; >= 0
};

struct MeanShiftResult {
  Eigen::Vector2d mode = Eigen::Vector2d::Zero();
  int iterations = 0;
  int support = 0;            // points within h of the final mode
  double support_weight = 0;  // their summed weight
  // False when no point lies within h of the estimate (nothing to shift towards) or the iteration
  // limit was reached while still moving; `mode` is then the last estimate, not a mode.
  bool converged = false;
};

// Checks the inputs (InvalidInput naming the problem: non-positive or non-finite radius, no points,
// a non-finite point, start or weight, negative weights, weights not matching the points), then
// iterates from `start`. `weights` may be empty (all 1).
Result<MeanShiftResult> MeanShiftMode(std::span<const Eigen::Vector2d> points,
                                      std::span<const double> weights, const Eigen::Vector2d& start,
                                      const MeanShiftOptions& options);

// The plain (unweighted) mean of `points`: the paper's starting point. InvalidInput when empty.
Result<Eigen::Vector2d> SampleMean(std::span<const Eigen::Vector2d> points);

}  // namespace fleetloc::mapmatch
