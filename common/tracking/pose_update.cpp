// Iterated Kalman pose update with iterative outlier rejection.
#include "tracking/pose_update.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace fleetloc::tracking {
namespace {

using geometry::Difference;
using geometry::Pose2;
using geometry::PoseWithCovariance;

// Iterated EKF: x ← x̂ + (P⁻¹ + HᵀR⁻¹H)⁻¹ HᵀR⁻¹ (z − h(x) − H(x̂ − x)), linearized at x.
PoseWithCovariance Solve(const PoseWithCovariance& prior, const std::vector<Correspondence>& m,
                         const std::vector<bool>& active) {
  const Eigen::Matrix3d prior_information = prior.covariance.inverse();
  Pose2 x = prior.pose;
  Eigen::Matrix3d information = prior_information;
  for (int iteration = 0; iteration < 5; ++iteration) {
    information = prior_information;
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    const Eigen::Vector3d prior_offset = Difference(prior.pose, x);
    for (size_t i = 0; i < m.size(); ++i) {
      if (!active[i]) continue;
      const Eigen::Matrix<double, 2, 3> h = geometry::PointJacobian(x, m[i].ground);
      const Eigen::Vector2d innovation = m[i].observed - x * m[i].ground - h * prior_offset;
      const double w = 1.0 / (m[i].sigma_m * m[i].sigma_m);
      information += w * h.transpose() * h;
      rhs += w * h.transpose() * innovation;
    }
    const Eigen::Vector3d step = information.ldlt().solve(rhs);
    const Pose2 next{prior.pose.x + step.x(), prior.pose.y + step.y(),
                     geometry::WrapAngle(prior.pose.theta + step.z())};
    const bool converged = Difference(next, x).norm() < 1e-10;
    x = next;
    if (converged) break;
  }
  return {x, information.inverse()};
}

std::vector<double> Residuals(const Pose2& pose, const std::vector<Correspondence>& m) {
  std::vector<double> r(m.size());
  for (size_t i = 0; i < m.size(); ++i) r[i] = (m[i].observed - pose * m[i].ground).norm();
  return r;
}

// Index of an active correspondence whose residual is markedly above the rest, or -1.
int MarkedOutlier(const std::vector<double>& residuals, const std::vector<bool>& active,
                  const OutlierOptions& options) {
  int worst = -1;
  std::vector<double> others;
  for (size_t i = 0; i < residuals.size(); ++i) {
    if (!active[i]) continue;
    if (worst < 0 || residuals[i] > residuals[worst]) worst = static_cast<int>(i);
  }
  for (size_t i = 0; i < residuals.size(); ++i) {
    if (active[i] && static_cast<int>(i) != worst) others.push_back(residuals[i]);
  }
  if (worst < 0 || others.empty()) return -1;
  std::nth_element(others.begin(), others.begin() + others.size() / 2, others.end());
  const double median = others[others.size() / 2];
  const double limit = std::max(options.ratio * median, options.min_residual_m);
  return residuals[worst] > limit ? worst : -1;
}

}  // namespace

PoseUpdate KalmanPoseUpdate(const PoseWithCovariance& prior,
                            const std::vector<Correspondence>& matches,
                            const OutlierOptions& options) {
  PoseUpdate result{prior, std::vector<bool>(matches.size(), false), 0, 0.0};
  if (matches.size() < 2) return result;
  std::vector<bool> active(matches.size(), true);
  int count = static_cast<int>(matches.size());
  PoseWithCovariance posterior = Solve(prior, matches, active);
  while (count > std::max(options.min_inliers, 2)) {
    const int outlier = MarkedOutlier(Residuals(posterior.pose, matches), active, options);
    if (outlier < 0) break;
    active[outlier] = false;
    --count;
    posterior = Solve(prior, matches, active);
  }
  const std::vector<double> residuals = Residuals(posterior.pose, matches);
  double sum_sq = 0.0;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (active[i]) sum_sq += residuals[i] * residuals[i];
  }
  result.posterior = posterior;
  result.inlier = active;
  result.inliers = count;
  result.rms_residual_m = std::sqrt(sum_sq / count);
  return result;
}

}  // namespace fleetloc::tracking
