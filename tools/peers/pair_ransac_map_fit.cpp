// Correspondence-free RANSAC map fit (see pair_ransac_map_fit.h).
#include "peers/pair_ransac_map_fit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "mapmatch/pair_votes.h"
#include "peers/landmark_index.h"
#include "peers/map_fit_peers.h"

namespace fleetloc::peers {
namespace {

// What every hypothesis is checked against: the points moved by the initial guess (all
// hypotheses are steps from there), and the landmark look-ups.
struct Search {
  std::span<const Eigen::Vector2d> landmarks;
  std::vector<Eigen::Vector2d> moved;
  LandmarkGrid grid;
  LandmarkPairTable pairs;
  const PairRansacOptions& options;
};

// The points `step` puts within the inlier threshold of a landmark; gives up (returning at most
// `best`) as soon as it cannot beat `best`.
int CountInliers(const Search& s, const geometry::Pose2& step, int best) {
  const Eigen::Rotation2Dd turn(step.theta);
  const Eigen::Vector2d shift(step.x, step.y);
  const int n = static_cast<int>(s.moved.size());
  int inliers = 0;
  for (int i = 0; i < n; ++i) {
    if (s.grid.NearestWithin(turn * s.moved[i] + shift) >= 0) {
      ++inliers;
    } else if (inliers + (n - 1 - i) <= best) {
      return inliers;
    }
  }
  return inliers;
}

// Samples point pairs needed to draw two inliers with the configured confidence at inlier ratio
// `ratio` (the standard RANSAC formula), capped by max_samples.
int SamplesNeeded(double ratio, const PairRansacOptions& o) {
  const double both = ratio * ratio;
  if (both <= 0.0) return o.max_samples;
  if (both >= 1.0) return 1;
  const double needed = std::log(1.0 - o.confidence) / std::log(1.0 - both);
  return static_cast<int>(std::min<double>(std::ceil(needed), o.max_samples));
}

struct Best {
  geometry::Pose2 step;
  int inliers = 0;
  int hypotheses = 0;
};

// Scores the corrections putting points a and b on every landmark pair of their length (both
// ways round), each landmark within the search radius of its point.
void TryPointPair(const Search& s, const Eigen::Vector2d& a, const Eigen::Vector2d& b, Best* best) {
  const PairRansacOptions& o = s.options;
  const double tolerance =
      o.distance_tolerance_m > 0 ? o.distance_tolerance_m : 2.0 * o.inlier_threshold_m;
  const double reach2 = o.search_radius_m * o.search_radius_m;
  const auto near = [&](const Eigen::Vector2d& p, int m) {
    return o.search_radius_m <= 0 || (s.landmarks[m] - p).squaredNorm() <= reach2;
  };
  for (const LandmarkPair& pair : s.pairs.Matching((a - b).norm(), tolerance)) {
    for (const auto& [ma, mb] : {std::pair{pair.a, pair.b}, std::pair{pair.b, pair.a}}) {
      if (best->hypotheses >= o.max_hypotheses) return;
      if (!near(a, ma) || !near(b, mb)) continue;
      ++best->hypotheses;
      const geometry::Pose2 step =
          mapmatch::RigidFromTwoPairs(a, b, s.landmarks[ma], s.landmarks[mb]);
      const int inliers = CountInliers(s, step, best->inliers);
      if (inliers > best->inliers) {
        best->step = step;
        best->inliers = inliers;
      }
    }
  }
}

// Draws point pairs until the adaptive sample count, the sample cap or the hypothesis cap.
Best Sample(const Search& s) {
  const PairRansacOptions& o = s.options;
  std::mt19937 rng(o.seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(s.moved.size()) - 1);
  const double n = static_cast<double>(s.moved.size());
  const double min_distance2 = o.min_pair_distance_m * o.min_pair_distance_m;
  Best best;
  for (int drawn = 0;
       drawn < SamplesNeeded(best.inliers / n, o) && best.hypotheses < o.max_hypotheses; ++drawn) {
    const Eigen::Vector2d& a = s.moved[pick(rng)];
    const Eigen::Vector2d& b = s.moved[pick(rng)];
    if ((a - b).squaredNorm() >= min_distance2) TryPointPair(s, a, b, &best);
  }
  return best;
}

// Least squares on the inliers of `step` (each point with its nearest landmark within the inlier
// threshold), re-paired each round; stops early when fewer than two pairs remain.
geometry::Pose2 Refine(const Search& s, geometry::Pose2 step) {
  for (int round = 0; round < s.options.refine_rounds; ++round) {
    std::vector<Eigen::Vector2d> from, to;
    for (const Eigen::Vector2d& p : s.moved) {
      const int m = s.grid.NearestWithin(step * p);
      if (m >= 0) {
        from.push_back(p);
        to.push_back(s.landmarks[m]);
      }
    }
    if (from.size() < 2) break;
    step = RigidFit(from, to);
  }
  return step;
}

// Fills the result's inlier statistics for `step` from the initial guess.
void Measure(const Search& s, const geometry::Pose2& step, mapmatch::MapFitResult* result) {
  std::vector<bool> landed(s.landmarks.size(), false);
  double squared = 0.0;
  for (const Eigen::Vector2d& p : s.moved) {
    const Eigen::Vector2d q = step * p;
    const int m = s.grid.NearestWithin(q);
    if (m < 0) continue;
    ++result->inliers;
    squared += (s.landmarks[m] - q).squaredNorm();
    landed[m] = true;
  }
  result->landmarks_matched = static_cast<int>(std::count(landed.begin(), landed.end(), true));
  if (result->inliers > 0) result->rms_residual_m = std::sqrt(squared / result->inliers);
}

}  // namespace

mapmatch::MapFitResult PairRansacMapFit(std::span<const Eigen::Vector2d> landmarks,
                                        std::span<const Eigen::Vector2d> points,
                                        const geometry::Pose2& initial,
                                        const PairRansacOptions& options) {
  Search search{landmarks,
                {},
                LandmarkGrid(landmarks, options.inlier_threshold_m),
                LandmarkPairTable(landmarks),
                options};
  for (const Eigen::Vector2d& p : points) search.moved.push_back(initial * p);
  const Best best = Sample(search);
  mapmatch::MapFitResult result;
  result.iterations = best.hypotheses;
  result.correction = initial;
  if (best.inliers < options.min_inliers) {
    result.reason = best.hypotheses == 0 ? "RANSAC: no point pair matches a landmark pair"
                                         : "RANSAC: too few inliers";
    return result;
  }
  const geometry::Pose2 step = Refine(search, best.step);
  Measure(search, step, &result);
  result.correction = step * initial;
  result.converged = result.inliers >= options.min_inliers;
  if (!result.converged) result.reason = "RANSAC: too few inliers after refinement";
  return result;
}

}  // namespace fleetloc::peers
