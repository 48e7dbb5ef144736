// Mean-shift mode search with the Epanechnikov kernel (see mean_shift.h).
#include "mapmatch/mean_shift.h"

#include <cmath>
#include <string>

namespace fleetloc::mapmatch {
namespace {

Status CheckInputs(std::span<const Eigen::Vector2d> points, std::span<const double> weights,
                   const Eigen::Vector2d& start, const MeanShiftOptions& options) {
  if (!std::isfinite(options.radius) || options.radius <= 0.0)
    return InvalidInput("mean shift: radius must be a positive number, got " +
                        std::to_string(options.radius));
  if (options.max_iterations <= 0) return InvalidInput("mean shift: max_iterations must be > 0");
  if (!(options.tolerance >= 0.0)) return InvalidInput("mean shift: tolerance must be >= 0");
  if (points.empty()) return InvalidInput("mean shift: no points");
  if (!start.allFinite()) return InvalidInput("mean shift: the start is not finite");
  if (!weights.empty() && weights.size() != points.size())
    return InvalidInput("mean shift: " + std::to_string(weights.size()) + " weights for " +
                        std::to_string(points.size()) + " points");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      return InvalidInput("mean shift: point " + std::to_string(i) + " is not finite");
    if (!weights.empty() && !(std::isfinite(weights[i]) && weights[i] >= 0.0))
      return InvalidInput("mean shift: weight " + std::to_string(i) +
                          " is not a finite number >= 0");
  }
  return Status::Ok();
}

struct Window {
  Eigen::Vector2d weighted_sum = Eigen::Vector2d::Zero();
  double weight = 0.0;
  int count = 0;
};

// The points within h of `center` (the Epanechnikov kernel's shadow is the flat kernel: the mean
// shift step is the plain weighted mean of the window).
Window Gather(std::span<const Eigen::Vector2d> points, std::span<const double> weights,
              const Eigen::Vector2d& center, double radius) {
  Window window;
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if ((points[i] - center).squaredNorm() >= r2) continue;
    const double w = weights.empty() ? 1.0 : weights[i];
    window.weighted_sum += w * points[i];
    window.weight += w;
    ++window.count;
  }
  return window;
}

}  // namespace

Result<MeanShiftResult> MeanShiftMode(std::span<const Eigen::Vector2d> points,
                                      std::span<const double> weights, const Eigen::Vector2d& start,
                                      const MeanShiftOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(CheckInputs(points, weights, start, options));
  MeanShiftResult result;
  result.mode = start;
  const double stop = options.tolerance * options.radius;
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    const Window window = Gather(points, weights, result.mode, options.radius);
    result.support = window.count;
    result.support_weight = window.weight;
    if (window.weight <= 0.0) return result;  // nothing within h: not converged
    const Eigen::Vector2d next = window.weighted_sum / window.weight;
    const double step = (next - result.mode).norm();
    result.mode = next;
    if (step <= stop) {
      result.converged = true;
      break;
    }
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  const Window final_window = Gather(points, weights, result.mode, options.radius);
  result.support = final_window.count;
  result.support_weight = final_window.weight;
  return result;
}

Result<Eigen::Vector2d> SampleMean(std::span<const Eigen::Vector2d> points) {
  if (points.empty()) return InvalidInput("sample mean: no points");
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) sum += p;
  return Eigen::Vector2d(sum / static_cast<double>(points.size()));
}

}  // namespace fleetloc::mapmatch
