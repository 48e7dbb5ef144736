// Synthetic map-fit problems (see map_fit_problem.h).
#include "mapmatch/map_fit_problem.h"

#include <algorithm>
#include <cmath>

namespace fleetloc::mapmatch {

MapFitProblem SimulateMapFitProblem(std::span<const Eigen::Vector2d> landmarks,
                                    std::span<const int> observed, const geometry::Pose2& truth,
                                    const MapFitProblemOptions& options, std::mt19937& rng) {
  MapFitProblem problem;
  problem.truth = truth;
  const geometry::Pose2 drift = truth.Inverse();
  std::normal_distribution<double> noise(0.0, options.noise_sigma_m);
  Eigen::Vector2d low = Eigen::Vector2d::Constant(INFINITY), high = -low;
  for (const int index : observed) {
    const Eigen::Vector2d& landmark = landmarks[index];
    low = low.cwiseMin(landmark);
    high = high.cwiseMax(landmark);
    for (int k = 0; k < options.points_per_landmark; ++k) {
      problem.points.push_back(
          drift * Eigen::Vector2d(landmark.x() + noise(rng), landmark.y() + noise(rng)));
    }
  }
  problem.inliers = static_cast<int>(problem.points.size());
  const int outliers = static_cast<int>(
      std::lround(problem.inliers * options.outlier_fraction / (1.0 - options.outlier_fraction)));
  low.array() -= options.outlier_margin_m;
  high.array() += options.outlier_margin_m;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < outliers; ++k) {
    const Eigen::Vector2d u(unit(rng), unit(rng));
    problem.points.push_back(drift * Eigen::Vector2d(low + u.cwiseProduct(high - low)));
  }
  std::shuffle(problem.points.begin(), problem.points.end(), rng);
  return problem;
}

CorrectionError ErrorOf(const geometry::Pose2& estimate, const geometry::Pose2& truth) {
  return {std::hypot(estimate.x - truth.x, estimate.y - truth.y),
          std::abs(geometry::WrapAngle(estimate.theta - truth.theta))};
}

}  // namespace fleetloc::mapmatch
