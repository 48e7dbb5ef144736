// Robust SE(2) map fit (paper 001 §4, docs/architecture.md): the correction T = (dx, dy, dθ) that
// moves measured floor points onto a landmark map. Each landmark attracts the transformed points
// within the kernel radius h; one iteration solves the linearised weighted least-squares step over
// those pairs, Δ = (Σ w JᵀJ)⁻¹ Σ w Jᵀ(m_j − T(p_i)), and T ← T + Δ. Outliers farther than h from
// every landmark and landmarks with no measurement nearby drop out by themselves. The fit is local:
// it converges to the truth from a start within about h of it, and to whatever mode is nearest from
// anywhere else — robust_map_fit.h gives it good starts and checks what it converged to.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::mapmatch {

struct MapFitOptions {
  double radius_m = 0.0;  // h at the first iteration; > 0
  // Each time the fit settles at the current h, h shrinks by `shrink_factor`, down to
  // `final_radius_m` (0: no shrinking, h stays radius_m). A wide first window reaches a far start;
  // a narrow last one keeps nearby outliers out of the estimate.
  double final_radius_m = 0.0;  // 0 or in (0, radius_m]
  double shrink_factor = 0.7;   // in (0, 1]
  int max_iterations = 100;     // > 0
  // The fit has settled at an h when a step is shorter than both; >= 0.
  double translation_tolerance_m = 1e-6;
  double rotation_tolerance_rad = 1e-7;
  int min_inliers = 3;  // fewer pairs than this is not a fit; >= 2
};

// InvalidInput naming the first option out of range.
Status Validate(const MapFitOptions& options);

struct MapFitResult {
  geometry::Pose2 correction;  // T = (dx, dy, dtheta): rotation about the map origin, then shift
  // Covariance of (dx, dy, dtheta) from the final normal equations scaled by the residual scatter
  // of the pairs: σ² (Σ w JᵀJ)⁻¹, σ² = Σ w|r|² / (2n − 3). Zero when not converged.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  int iterations = 0;
  int inliers = 0;            // point–landmark pairs within the final h under the final T
  int landmarks_matched = 0;  // landmarks with at least one pair
  double rms_residual_m = 0.0;
  double final_radius_m = 0.0;  // h at the last iteration
  // Kernel support of the final pairs, Σ w (1 − |r|²/h²) over the pairs within the final h: the
  // Epanechnikov density the mean shift climbs, how much of the data the correction explains.
  double support = 0.0;
  // Set by the robust fit (robust_map_fit.h): the starting corrections it refined, and whether a
  // distinct correction is supported almost as well (its support in runner_up_support; the fit is
  // then not converged).
  int starts = 1;
  bool ambiguous = false;
  double runner_up_support = 0.0;
  // False when the pairs cannot determine T (fewer than min_inliers, or a single landmark cluster
  // so the rotation is unobservable) or the iteration limit was reached while still moving;
  // `correction` is then the last estimate, not a fit, and `reason` says why.
  bool converged = false;
  std::string reason;
};

// Two landmarks closer than this are one landmark listed twice: a broken map.
inline constexpr double kSameLandmarkM = 1e-6;

// The indices (ascending) of two landmarks closer than kSameLandmarkM, if any. O(n log n) for
// landmarks spread along x.
std::optional<std::pair<std::size_t, std::size_t>> FindDuplicateLandmarks(
    std::span<const Eigen::Vector2d> landmarks);

// InvalidInput naming the problem for no landmarks or points, a non-finite landmark, point, weight
// or initial value, weights not one per point or negative, or two landmarks at the same position.
Status CheckMapFitInputs(std::span<const Eigen::Vector2d> landmarks,
                         std::span<const Eigen::Vector2d> points, std::span<const double> weights,
                         const geometry::Pose2& initial);

// The point–landmark pairs within h under a correction, measured without fitting.
struct PairStatistics {
  int pairs = 0;
  double support = 0.0;                      // Σ w (1 − |r|²/h²)
  double rms_residual_m = 0.0;               // weighted, 0 without pairs
  std::vector<int> pairs_per_landmark;       // one count per landmark
  std::vector<std::pair<int, int>> matches;  // (point, landmark) of every pair, ascending
};
// Requires h > 0 and inputs that passed CheckMapFitInputs.
PairStatistics MeasurePairs(std::span<const Eigen::Vector2d> landmarks,
                            std::span<const Eigen::Vector2d> points,
                            std::span<const double> weights, const geometry::Pose2& correction,
                            double radius_m);

// Fits T starting from `initial`. `weights` (one per point, finite, >= 0) may be empty (all 1).
// InvalidInput naming the problem for bad options, no landmarks or points, a non-finite landmark,
// point, weight or initial value, or two landmarks at the same position (closer than 1 µm).
// Degenerate geometry is not an error: it returns converged false with the reason.
Result<MapFitResult> FitMap(std::span<const Eigen::Vector2d> landmarks,
                            std::span<const Eigen::Vector2d> points,
                            std::span<const double> weights, const geometry::Pose2& initial,
                            const MapFitOptions& options);

}  // namespace fleetloc::mapmatch
