// Robust SE(2) map fit by Gauss–Newton over the point–landmark pairs within h (see map_fit.h).
//
// Neighbour search is brute force, O(points × landmarks) per iteration. Measured
// (docs/benchmarks.md, "Map fit"): 0.13–1.0 ms per fit for 100–500 points against a 36-landmark map
// on one core, which is small next to a detection window of seconds; the global position update
// crops the map to the window's points first, so a building-sized map costs the same. A grid would
// cut the constant but not change what the vehicle can do, so it is left out until a profile says
// otherwise.
#include "mapmatch/map_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

namespace fleetloc::mapmatch {
namespace {

std::string Num(double value) { return std::to_string(value); }

Status CheckFinite(std::span<const Eigen::Vector2d> xy, const std::string& what) {
  for (std::size_t i = 0; i < xy.size(); ++i) {
    if (!xy[i].allFinite())
      return InvalidInput("map fit: " + what + " " + std::to_string(i) + " is not finite");
  }
  return Status::Ok();
}

Status CheckWeights(std::span<const double> weights, std::size_t points) {
  if (weights.empty()) return Status::Ok();
  if (weights.size() != points) {
    return InvalidInput("map fit: " + std::to_string(weights.size()) + " weights for " +
                        std::to_string(points) + " points");
  }
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (!(std::isfinite(weights[i]) && weights[i] >= 0.0))
      return InvalidInput("map fit: weight " + std::to_string(i) + " is not a finite number >= 0");
  }
  return Status::Ok();
}

// The weighted normal equations of one Gauss–Newton step over the pairs within h of a landmark.
struct NormalEquations {
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();   // Σ w JᵀJ
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();  // Σ w Jᵀ r
  double weighted_squared_residual = 0.0;              // Σ w |r|²
  double weight = 0.0;                                 // Σ w
  double kernel_support = 0.0;                         // Σ w (1 − |r|²/h²)
  int pairs = 0;
  std::vector<int> pairs_per_landmark;
  std::vector<int> matched_landmarks;        // indices of landmarks with at least one pair
  std::vector<std::pair<int, int>> matches;  // (point, landmark) of every pair
};

NormalEquations Accumulate(std::span<const Eigen::Vector2d> landmarks,
                           std::span<const Eigen::Vector2d> points, std::span<const double> weights,
                           const geometry::Pose2& t, double radius) {
  NormalEquations eq;
  eq.pairs_per_landmark.assign(landmarks.size(), 0);
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (w <= 0.0) continue;
    const Eigen::Vector2d moved = t * points[i];
    Eigen::Matrix<double, 2, 3> j;
    bool have_jacobian = false;  // only points that pair need it
    for (std::size_t m = 0; m < landmarks.size(); ++m) {
      const Eigen::Vector2d r = landmarks[m] - moved;
      if (r.squaredNorm() >= r2) continue;
      if (!have_jacobian) {
        j = geometry::PointJacobian(t, points[i]);
        have_jacobian = true;
      }
      eq.hessian += w * j.transpose() * j;
      eq.gradient += w * j.transpose() * r;
      eq.weighted_squared_residual += w * r.squaredNorm();
      eq.weight += w;
      eq.kernel_support += w * (1.0 - r.squaredNorm() / r2);
      ++eq.pairs;
      ++eq.pairs_per_landmark[m];
      eq.matches.emplace_back(static_cast<int>(i), static_cast<int>(m));
    }
  }
  for (std::size_t m = 0; m < landmarks.size(); ++m)
    if (eq.pairs_per_landmark[m] > 0) eq.matched_landmarks.push_back(static_cast<int>(m));
  return eq;
}

// The rotation is observable when the pairs form at least two distinguishable clusters: two
// matched landmarks more than h apart (paper §5). One cluster pins the translation only.
bool RotationObservable(const NormalEquations& eq, std::span<const Eigen::Vector2d> landmarks,
                        double radius) {
  const std::vector<int>& m = eq.matched_landmarks;
  for (std::size_t a = 0; a < m.size(); ++a)
    for (std::size_t b = a + 1; b < m.size(); ++b)
      if ((landmarks[m[a]] - landmarks[m[b]]).norm() > radius) return true;
  return false;
}

// Empty when the pairs determine T; otherwise why they do not.
std::string Undetermined(const NormalEquations& eq, std::span<const Eigen::Vector2d> landmarks,
                         double radius, int min_inliers) {
  if (eq.pairs < min_inliers) {
    return "only " + std::to_string(eq.pairs) + " point-landmark pairs within h = " + Num(radius) +
           " (need " + std::to_string(min_inliers) + ")";
  }
  if (!RotationObservable(eq, landmarks, radius)) {
    return "rotation unobservable: the pairs match " + std::to_string(eq.matched_landmarks.size()) +
           " landmark(s) but no two more than h = " + Num(radius) + " apart";
  }
  return "";
}

// Fills the statistics of the final pairs; the covariance only when the fit converged.
void Summarize(const NormalEquations& eq, MapFitResult* result) {
  result->inliers = eq.pairs;
  result->landmarks_matched = static_cast<int>(eq.matched_landmarks.size());
  result->rms_residual_m = eq.weight > 0 ? std::sqrt(eq.weighted_squared_residual / eq.weight) : 0;
  result->support = eq.kernel_support;
  if (!result->converged) return;
  const double sigma2 = eq.weighted_squared_residual / (2.0 * eq.pairs - 3.0);
  result->covariance = sigma2 * eq.hessian.inverse();
}

}  // namespace

Status CheckMapFitInputs(std::span<const Eigen::Vector2d> landmarks,
                         std::span<const Eigen::Vector2d> points, std::span<const double> weights,
                         const geometry::Pose2& initial) {
  if (landmarks.empty()) return InvalidInput("map fit: no landmarks");
  if (points.empty()) return InvalidInput("map fit: no points");
  if (!initial.ToVector().allFinite())
    return InvalidInput("map fit: the initial correction is not finite");
  FLEETLOC_RETURN_IF_ERROR(CheckFinite(landmarks, "landmark"));
  FLEETLOC_RETURN_IF_ERROR(CheckFinite(points, "point"));
  FLEETLOC_RETURN_IF_ERROR(CheckWeights(weights, points.size()));
  if (const auto duplicate = FindDuplicateLandmarks(landmarks)) {
    return InvalidInput("map fit: landmarks " + std::to_string(duplicate->first) + " and " +
                        std::to_string(duplicate->second) + " are at the same position");
  }
  return Status::Ok();
}

PairStatistics MeasurePairs(std::span<const Eigen::Vector2d> landmarks,
                            std::span<const Eigen::Vector2d> points,
                            std::span<const double> weights, const geometry::Pose2& correction,
                            double radius_m) {
  FLEETLOC_CHECK(radius_m > 0.0);
  NormalEquations eq = Accumulate(landmarks, points, weights, correction, radius_m);
  PairStatistics stats;
  stats.pairs = eq.pairs;
  stats.support = eq.kernel_support;
  stats.rms_residual_m = eq.weight > 0 ? std::sqrt(eq.weighted_squared_residual / eq.weight) : 0;
  stats.pairs_per_landmark = std::move(eq.pairs_per_landmark);
  stats.matches = std::move(eq.matches);
  return stats;
}

std::optional<std::pair<std::size_t, std::size_t>> FindDuplicateLandmarks(
    std::span<const Eigen::Vector2d> landmarks) {
  std::vector<std::size_t> order(landmarks.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return landmarks[a].x() < landmarks[b].x(); });
  for (std::size_t k = 0; k < order.size(); ++k) {
    for (std::size_t n = k + 1; n < order.size(); ++n) {  // only neighbours along x
      if (landmarks[order[n]].x() - landmarks[order[k]].x() >= kSameLandmarkM) break;
      if ((landmarks[order[n]] - landmarks[order[k]]).norm() < kSameLandmarkM)
        return std::minmax(order[k], order[n]);
    }
  }
  return std::nullopt;
}

Status Validate(const MapFitOptions& o) {
  if (!(std::isfinite(o.radius_m) && o.radius_m > 0.0))
    return InvalidInput("map fit: radius must be a positive number, got " + Num(o.radius_m));
  if (!(o.final_radius_m == 0.0 || (o.final_radius_m > 0.0 && o.final_radius_m <= o.radius_m)))
    return InvalidInput("map fit: final_radius_m must be 0 or in (0, radius], got " +
                        Num(o.final_radius_m));
  if (!(o.shrink_factor > 0.0 && o.shrink_factor <= 1.0))
    return InvalidInput("map fit: shrink_factor must be in (0, 1], got " + Num(o.shrink_factor));
  if (o.final_radius_m > 0.0 && o.final_radius_m < o.radius_m && o.shrink_factor == 1.0)
    return InvalidInput("map fit: shrink_factor must be < 1 when final_radius_m < radius");
  if (o.max_iterations <= 0) return InvalidInput("map fit: max_iterations must be > 0");
  if (!(o.translation_tolerance_m >= 0.0 && o.rotation_tolerance_rad >= 0.0))
    return InvalidInput("map fit: tolerances must be >= 0");
  if (o.min_inliers < 2) return InvalidInput("map fit: min_inliers must be >= 2");
  return Status::Ok();
}

Result<MapFitResult> FitMap(std::span<const Eigen::Vector2d> landmarks,
                            std::span<const Eigen::Vector2d> points,
                            std::span<const double> weights, const geometry::Pose2& initial,
                            const MapFitOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  FLEETLOC_RETURN_IF_ERROR(CheckMapFitInputs(landmarks, points, weights, initial));
  const double final_radius =
      options.final_radius_m > 0 ? options.final_radius_m : options.radius_m;
  MapFitResult result;
  result.correction = initial;
  double radius = options.radius_m;
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    const NormalEquations eq = Accumulate(landmarks, points, weights, result.correction, radius);
    result.reason = Undetermined(eq, landmarks, radius, options.min_inliers);
    if (!result.reason.empty()) break;
    const Eigen::LDLT<Eigen::Matrix3d> solver(eq.hessian);
    if (solver.info() != Eigen::Success || !solver.isPositive()) {
      result.reason = "the normal equations are singular";
      break;
    }
    const Eigen::Vector3d step = solver.solve(eq.gradient);
    result.correction = geometry::Pose2::FromVector(result.correction.ToVector() + step);
    result.correction.theta = geometry::WrapAngle(result.correction.theta);
    const bool settled = step.head<2>().norm() <= options.translation_tolerance_m &&
                         std::abs(step.z()) <= options.rotation_tolerance_rad;
    if (settled && radius <= final_radius) {
      result.converged = true;
      break;
    }
    if (settled) radius = std::max(final_radius, radius * options.shrink_factor);
  }
  if (result.iterations > options.max_iterations) {
    result.iterations = options.max_iterations;
    result.reason = "still moving after " + std::to_string(options.max_iterations) + " iterations";
  }
  result.final_radius_m = radius;
  Summarize(Accumulate(landmarks, points, weights, result.correction, radius), &result);
  return result;
}

}  // namespace fleetloc::mapmatch
