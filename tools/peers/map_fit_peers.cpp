// Nearest-landmark RANSAC and ICP map fits, and the rigid fit they share (see map_fit_peers.h).
#include "peers/map_fit_peers.h"

#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <vector>

namespace fleetloc::peers {
namespace {

// The landmark nearest to `xy` (brute force, as the mean-shift fit's pair search).
const Eigen::Vector2d& Nearest(std::span<const Eigen::Vector2d> landmarks,
                               const Eigen::Vector2d& xy) {
  std::size_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t m = 0; m < landmarks.size(); ++m) {
    const double d2 = (landmarks[m] - xy).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = m;
    }
  }
  return landmarks[best];
}

}  // namespace

mapmatch::MapFitResult NearestRansacMapFit(std::span<const Eigen::Vector2d> landmarks,
                                           std::span<const Eigen::Vector2d> points,
                                           const geometry::Pose2& initial,
                                           const NearestRansacOptions& options) {
  // Pairs relative to the points' centroid, so the dropped scale of the similarity cannot shift
  // the correction by (scale − 1) × the distance to the map origin.
  std::vector<Eigen::Vector2d> moved;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += moved.emplace_back(initial * p);
  centroid /= static_cast<double>(moved.size());
  std::vector<cv::Point2d> from, to;
  for (const Eigen::Vector2d& p : moved) {
    const Eigen::Vector2d m = Nearest(landmarks, p) - centroid;
    from.emplace_back(p.x() - centroid.x(), p.y() - centroid.y());
    to.emplace_back(m.x(), m.y());
  }
  std::vector<uchar> inliers;
  const cv::Mat a = cv::estimateAffinePartial2D(from, to, inliers, cv::RANSAC,
                                                options.inlier_threshold_m, options.max_iterations,
                                                options.confidence, options.refine_iterations);
  mapmatch::MapFitResult result;
  result.correction = initial;
  result.iterations = 1;
  if (a.empty()) {
    result.reason = "RANSAC found no model";
    return result;
  }
  const geometry::Pose2 step{a.at<double>(0, 2), a.at<double>(1, 2),
                             std::atan2(a.at<double>(1, 0), a.at<double>(0, 0))};
  const geometry::Pose2 at_centroid{centroid.x(), centroid.y(), 0.0};
  result.correction = at_centroid * step * at_centroid.Inverse() * initial;
  result.inliers = cv::countNonZero(inliers);
  result.converged = true;
  return result;
}

geometry::Pose2 RigidFit(const std::vector<Eigen::Vector2d>& from,
                         const std::vector<Eigen::Vector2d>& to) {
  Eigen::Vector2d from_mean = Eigen::Vector2d::Zero(), to_mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i) {
    from_mean += from[i];
    to_mean += to[i];
  }
  from_mean /= static_cast<double>(from.size());
  to_mean /= static_cast<double>(to.size());
  double dot = 0.0, cross = 0.0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector2d a = from[i] - from_mean, b = to[i] - to_mean;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  const double theta = std::atan2(cross, dot);
  const Eigen::Vector2d shift = to_mean - geometry::Pose2{0, 0, theta} * from_mean;
  return {shift.x(), shift.y(), theta};
}

mapmatch::MapFitResult IcpMapFit(std::span<const Eigen::Vector2d> landmarks,
                                 std::span<const Eigen::Vector2d> points,
                                 const geometry::Pose2& initial, const IcpMapFitOptions& options) {
  mapmatch::MapFitResult result;
  result.correction = initial;
  std::vector<Eigen::Vector2d> moved(points.size()), nearest(points.size());
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      moved[i] = result.correction * points[i];
      nearest[i] = Nearest(landmarks, moved[i]);
    }
    const geometry::Pose2 step = RigidFit(moved, nearest);
    result.correction = step * result.correction;
    if (std::hypot(step.x, step.y) <= options.translation_tolerance_m &&
        std::abs(step.theta) <= options.rotation_tolerance_rad) {
      result.converged = true;
      break;
    }
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  result.inliers = static_cast<int>(points.size());
  if (!result.converged) result.reason = "ICP still moving";
  return result;
}

}  // namespace fleetloc::peers
