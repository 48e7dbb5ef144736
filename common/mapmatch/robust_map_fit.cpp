// Robust map fit: voted starts, mean-shift refinement, mode choice by support, validation (see
// robust_map_fit.h).
//
// Cost: the dense spots and the pair vote are O(points log points + spots² × candidates²); each
// start's fit only sees the points and landmarks it can pair (those within twice its starting h of
// each other under the start). Measured in docs/benchmarks.md ("Map fit on cluttered rooms").
#include "mapmatch/robust_map_fit.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "mapmatch/dense_spots.h"
#include "mapmatch/pair_votes.h"

namespace fleetloc::mapmatch {
namespace {

std::string Num(double value) { return std::to_string(value); }

std::string Describe(const geometry::Pose2& t) {
  std::ostringstream text;
  text << "(" << t.x << ", " << t.y << ", " << t.theta << ")";
  return text.str();
}

struct Box {
  Eigen::Vector2d low, high;
};

Box BoxOf(std::span<const Eigen::Vector2d> xy) {
  Box box{xy.front(), xy.front()};
  for (const Eigen::Vector2d& p : xy) box.low = box.low.cwiseMin(p);
  for (const Eigen::Vector2d& p : xy) box.high = box.high.cwiseMax(p);
  return box;
}

// The problem as every start sees it: the landmarks within reach of the points, h at the end.
struct Problem {
  std::vector<Eigen::Vector2d> landmarks;
  std::span<const Eigen::Vector2d> points;
  std::span<const double> weights;
  Box extent;  // of the points (drifted frame): where two corrections must agree to be one
  double final_radius = 0.0;
  const RobustMapFitOptions& options;
};

// The landmarks within `reach` of the box of the points moved by `correction`.
std::vector<Eigen::Vector2d> LandmarksNear(std::span<const Eigen::Vector2d> landmarks,
                                           std::span<const Eigen::Vector2d> points,
                                           const geometry::Pose2& correction, double reach) {
  std::vector<Eigen::Vector2d> moved;
  moved.reserve(points.size());
  for (const Eigen::Vector2d& p : points) moved.push_back(correction * p);
  const Box box = BoxOf(moved);
  std::vector<Eigen::Vector2d> near;
  for (const Eigen::Vector2d& m : landmarks) {
    if ((m.array() >= box.low.array() - reach).all() &&
        (m.array() <= box.high.array() + reach).all())
      near.push_back(m);
  }
  return near;
}

// The points (with their weights) and landmarks within `reach` of each other under `correction`:
// all a fit starting there with h <= reach / 2 can pair.
struct Subset {
  std::vector<Eigen::Vector2d> landmarks, points;
  std::vector<double> weights;
};
Subset PairablePart(const Problem& problem, const geometry::Pose2& correction, double reach) {
  Subset subset;
  std::vector<char> used(problem.landmarks.size(), 0);
  for (std::size_t i = 0; i < problem.points.size(); ++i) {
    const Eigen::Vector2d moved = correction * problem.points[i];
    bool near = false;
    for (std::size_t m = 0; m < problem.landmarks.size(); ++m) {
      if ((problem.landmarks[m] - moved).squaredNorm() >= reach * reach) continue;
      near = true;
      used[m] = 1;
    }
    if (!near) continue;
    subset.points.push_back(problem.points[i]);
    if (!problem.weights.empty()) subset.weights.push_back(problem.weights[i]);
  }
  for (std::size_t m = 0; m < used.size(); ++m)
    if (used[m]) subset.landmarks.push_back(problem.landmarks[m]);
  return subset;
}

// A start refined by the mean-shift fit, and its pairs over all points at the final h.
struct Mode {
  MapFitResult fit;
  PairStatistics pairs;
};

MapFitOptions FitOptions(const Problem& problem, double start_radius) {
  const RobustMapFitOptions& o = problem.options;
  return {.radius_m = start_radius,
          .final_radius_m = problem.final_radius,
          .shrink_factor = start_radius > problem.final_radius ? o.shrink_factor : 1.0,
          .max_iterations = o.max_iterations};
}

// `stats` measured on landmarks[index[k]] (k the index it was measured with), renumbered to index
// into `count` landmarks.
PairStatistics Renumbered(PairStatistics stats, const std::vector<int>& index, std::size_t count) {
  std::vector<int> per_landmark(count, 0);
  for (std::size_t k = 0; k < index.size(); ++k)
    per_landmark[index[k]] = stats.pairs_per_landmark[k];
  stats.pairs_per_landmark = std::move(per_landmark);
  for (auto& match : stats.matches) match.second = index[match.second];
  std::sort(stats.matches.begin(), stats.matches.end());
  return stats;
}

// The mode refitted on the landmarks it lands on (min_points_per_landmark points within h) and
// its pairs with those only: a lone point near another landmark is an outlier, neither pulling
// the fit nor counting as support.
void KeepToLandedLandmarks(const Problem& problem, const Subset& part, Mode* mode) {
  const double h = problem.final_radius;
  const PairStatistics all =
      MeasurePairs(problem.landmarks, problem.points, problem.weights, mode->fit.correction, h);
  std::vector<int> index;
  std::vector<Eigen::Vector2d> landed;
  for (std::size_t m = 0; m < problem.landmarks.size(); ++m) {
    if (all.pairs_per_landmark[m] < problem.options.min_points_per_landmark) continue;
    index.push_back(static_cast<int>(m));
    landed.push_back(problem.landmarks[m]);
  }
  if (landed.size() >= 2) {
    MapFitResult refit = FitMap(landed, part.points, part.weights, mode->fit.correction,
                                {.radius_m = h, .max_iterations = problem.options.max_iterations})
                             .value();
    if (refit.converged) {
      refit.iterations += mode->fit.iterations;
      mode->fit = std::move(refit);
    }
  }
  mode->pairs =
      Renumbered(MeasurePairs(landed, problem.points, problem.weights, mode->fit.correction, h),
                 index, problem.landmarks.size());
}

Subset Whole(const Problem& problem) {
  return {problem.landmarks,
          {problem.points.begin(), problem.points.end()},
          {problem.weights.begin(), problem.weights.end()}};
}

// The mean-shift fit from `start`, h shrinking from start_radius to the final radius, over all
// points or over those it can pair (voted starts, which are close), then kept to the landmarks
// it lands on.
Mode Refine(const Problem& problem, const geometry::Pose2& start, double start_radius,
            bool all_points) {
  Mode mode;
  const Subset part =
      all_points ? Whole(problem) : PairablePart(problem, start, 2.0 * start_radius);
  if (part.points.empty() || part.landmarks.empty()) {
    mode.fit.reason = "no point within h of a landmark";
    return mode;
  }
  mode.fit =
      FitMap(part.landmarks, part.points, part.weights, start, FitOptions(problem, start_radius))
          .value();
  if (mode.fit.converged) KeepToLandedLandmarks(problem, part, &mode);
  return mode;
}

// A voted correction (from two spots) refined by the mean-shift fit of all spots, weighted by
// their support, with h = the final radius: the other spots it puts on landmarks fix its
// rotation. The voted correction itself when fewer than two other spots help.
geometry::Pose2 FitToSpots(const Problem& problem, const std::vector<DenseSpot>& spots,
                           const geometry::Pose2& voted) {
  std::vector<Eigen::Vector2d> centers(spots.size());
  std::vector<double> supports(spots.size());
  std::ranges::transform(spots, centers.begin(), &DenseSpot::center);
  std::ranges::transform(spots, supports.begin(), &DenseSpot::support);
  const MapFitResult fit = FitMap(problem.landmarks, centers, supports, voted,
                                  {.radius_m = problem.final_radius,
                                   .max_iterations = problem.options.max_iterations,
                                   .min_inliers = 3})
                               .value();
  return fit.converged ? fit.correction : voted;
}

// The starts: `initial` (h from the search radius, all points), then the voted corrections.
std::vector<Mode> RefineStarts(const Problem& problem, const geometry::Pose2& initial) {
  const RobustMapFitOptions& o = problem.options;
  std::vector<Mode> modes;
  modes.push_back(
      Refine(problem, initial, std::max(o.search_radius_m, problem.final_radius), true));
  if (o.max_voted_starts == 0) return modes;
  std::vector<Eigen::Vector2d> moved;
  moved.reserve(problem.points.size());
  for (const Eigen::Vector2d& p : problem.points) moved.push_back(initial * p);
  const std::vector<DenseSpot> spots =
      FindDenseSpots(moved, problem.weights, problem.final_radius, o.max_spots);
  const std::vector<VotedCorrection> voted =
      VoteCorrections(spots, problem.landmarks,
                      {.search_radius_m = o.search_radius_m,
                       .tolerance_m = problem.final_radius,
                       .min_pair_distance_m = o.min_pair_distance_m,
                       .max_corrections = o.max_voted_starts});
  const double start_radius =
      std::max(problem.final_radius, std::min(o.voted_start_radius_m, o.search_radius_m));
  for (const VotedCorrection& v : voted) {
    const geometry::Pose2 on_spots = FitToSpots(problem, spots, v.correction);
    modes.push_back(Refine(problem, on_spots * initial, start_radius, false));
  }
  return modes;
}

// Empty when the mode lands on enough landmarks, tightly; otherwise why not.
std::string ValidationFailure(const Mode& mode, const Problem& problem) {
  const RobustMapFitOptions& o = problem.options;
  const double h = problem.final_radius;
  const int landed = static_cast<int>(
      std::count_if(mode.pairs.pairs_per_landmark.begin(), mode.pairs.pairs_per_landmark.end(),
                    [&](int n) { return n >= o.min_points_per_landmark; }));
  if (landed < o.min_landmarks) {
    return "the best correction puts at least " + std::to_string(o.min_points_per_landmark) +
           " points within h = " + Num(h) + " of " + std::to_string(landed) +
           " landmark(s), fewer than " + std::to_string(o.min_landmarks) +
           (landed == 1 ? " (one landmark: rotation unobservable)" : "");
  }
  if (mode.pairs.rms_residual_m > o.max_rms_ratio * h) {
    return "the points within h = " + Num(h) + " of the landmarks are spread like outliers (rms " +
           Num(mode.pairs.rms_residual_m) +
           " m); if they are that noisy, h should be about three times their noise";
  }
  return "";
}

// The pairs of `mode` at the landmarks it lands on (at least min_points_per_landmark pairs).
std::vector<std::pair<int, int>> LandedPairs(const Mode& mode, int min_points_per_landmark) {
  std::vector<std::pair<int, int>> landed;
  for (const auto& match : mode.pairs.matches)
    if (mode.pairs.pairs_per_landmark[match.second] >= min_points_per_landmark)
      landed.push_back(match);
  return landed;
}

// Two modes are one reading of the points when they put the points alike (within h over their
// extent) or when they land the same points on the same landmarks (at least 80 % of the landed
// pairs of the weaker are pairs of the stronger: one of them pulled aside by a few stray points at
// a long lever). Landing one cluster on another landmark is another reading.
bool SameReading(const Mode& stronger, const Mode& weaker, const Problem& problem) {
  if (LargestDisagreement(stronger.fit.correction, weaker.fit.correction, problem.extent.low,
                          problem.extent.high) <= problem.final_radius)
    return true;
  const int min_points = problem.options.min_points_per_landmark;
  const std::vector<std::pair<int, int>> weak = LandedPairs(weaker, min_points);
  const std::vector<std::pair<int, int>> strong = LandedPairs(stronger, min_points);
  std::vector<std::pair<int, int>> shared;
  std::set_intersection(strong.begin(), strong.end(), weak.begin(), weak.end(),
                        std::back_inserter(shared));
  return !weak.empty() && shared.size() >= 0.8 * weak.size();
}

// Whether the mode moves every point it lands on a landmark by at most the search radius (grown
// by h) from where `initial` puts it: the search is bounded by the displacement it allows.
bool WithinSearch(const Mode& mode, const Problem& problem, const geometry::Pose2& initial) {
  const double reach = problem.options.search_radius_m + problem.final_radius;
  return std::all_of(mode.pairs.matches.begin(), mode.pairs.matches.end(), [&](const auto& match) {
    const Eigen::Vector2d& p = problem.points[match.first];
    return (mode.fit.correction * p - initial * p).squaredNorm() <= reach * reach;
  });
}

// The converged modes within the search, best supported first, one per distinct reading.
std::vector<const Mode*> DistinctModes(const std::vector<Mode>& modes, const Problem& problem,
                                       const geometry::Pose2& initial) {
  std::vector<const Mode*> sorted;
  for (const Mode& m : modes)
    if (m.fit.converged && WithinSearch(m, problem, initial)) sorted.push_back(&m);
  std::stable_sort(sorted.begin(), sorted.end(), [](const Mode* a, const Mode* b) {
    return a->pairs.support > b->pairs.support;
  });
  std::vector<const Mode*> distinct;
  for (const Mode* m : sorted) {
    const bool known = std::any_of(distinct.begin(), distinct.end(),
                                   [&](const Mode* d) { return SameReading(*d, *m, problem); });
    if (!known) distinct.push_back(m);
  }
  return distinct;
}

// The result of a fit that cannot be trusted: the initial correction, the reason, and the
// statistics of `examined` (the best mode looked at).
MapFitResult NotConverged(const MapFitResult& examined, const geometry::Pose2& initial,
                          const std::string& reason) {
  MapFitResult result = examined;
  result.converged = false;
  result.reason = reason;
  result.correction = initial;
  result.covariance.setZero();
  return result;
}

// Fills the statistics over all points at the final h into the chosen mode's fit.
MapFitResult Chosen(const Mode& mode) {
  MapFitResult result = mode.fit;
  result.inliers = mode.pairs.pairs;
  result.support = mode.pairs.support;
  result.rms_residual_m = mode.pairs.rms_residual_m;
  result.landmarks_matched = static_cast<int>(std::count_if(mode.pairs.pairs_per_landmark.begin(),
                                                            mode.pairs.pairs_per_landmark.end(),
                                                            [](int n) { return n > 0; }));
  return result;
}

MapFitResult ChooseMode(const std::vector<Mode>& modes, const Problem& problem,
                        const geometry::Pose2& initial) {
  const std::vector<const Mode*> distinct = DistinctModes(modes, problem, initial);
  if (distinct.empty()) {
    const MapFitResult& prior = modes.front().fit;
    return NotConverged(prior, initial,
                        prior.converged ? "no correction within the search radius " +
                                              Num(problem.options.search_radius_m) +
                                              " m lands the points on landmarks"
                                        : prior.reason);
  }
  std::vector<const Mode*> valid;
  for (const Mode* m : distinct)
    if (ValidationFailure(*m, problem).empty()) valid.push_back(m);
  if (valid.empty()) {
    return NotConverged(Chosen(*distinct.front()), initial,
                        ValidationFailure(*distinct.front(), problem));
  }
  MapFitResult result = Chosen(*valid.front());
  if (valid.size() < 2) return result;
  result.runner_up_support = valid[1]->pairs.support;
  if (result.runner_up_support < problem.options.ambiguity_ratio * result.support) return result;
  result = NotConverged(result, initial,
                        "ambiguous: corrections " + Describe(result.correction) + " and " +
                            Describe(valid[1]->fit.correction) + " are supported alike (" +
                            Num(result.support) + " and " + Num(result.runner_up_support) + ")");
  result.ambiguous = true;
  return result;
}

}  // namespace

Status Validate(const RobustMapFitOptions& o) {
  auto bad = [](const std::string& what) { return InvalidInput("robust map fit: " + what); };
  if (!(std::isfinite(o.search_radius_m) && o.search_radius_m > 0.0))
    return bad("search radius must be a positive number, got " + Num(o.search_radius_m));
  if (!(std::isfinite(o.final_radius_m) && o.final_radius_m > 0.0))
    return bad("final_radius_m must be > 0, got " + Num(o.final_radius_m));
  if (!(std::isfinite(o.voted_start_radius_m) && o.voted_start_radius_m > 0.0))
    return bad("voted_start_radius_m must be > 0");
  if (!(o.shrink_factor > 0.0 && o.shrink_factor < 1.0))
    return bad("shrink_factor must be in (0, 1), got " + Num(o.shrink_factor));
  if (o.max_iterations <= 0) return bad("max_iterations must be > 0");
  if (o.max_spots < 2) return bad("max_spots must be >= 2");
  if (o.max_voted_starts < 0) return bad("max_voted_starts must be >= 0");
  if (!(std::isfinite(o.min_pair_distance_m) && o.min_pair_distance_m >= 0.0))
    return bad("min_pair_distance_m must be >= 0");
  if (o.min_landmarks < 2) return bad("min_landmarks must be >= 2");
  if (o.min_points_per_landmark < 1) return bad("min_points_per_landmark must be >= 1");
  if (!(o.max_rms_ratio > 0.0 && o.max_rms_ratio <= 1.0))
    return bad("max_rms_ratio must be in (0, 1]");
  if (!(o.ambiguity_ratio > 0.0 && o.ambiguity_ratio <= 1.0))
    return bad("ambiguity_ratio must be in (0, 1]");
  return Status::Ok();
}

Result<MapFitResult> RobustFitMap(std::span<const Eigen::Vector2d> landmarks,
                                  std::span<const Eigen::Vector2d> points,
                                  std::span<const double> weights, const geometry::Pose2& initial,
                                  const RobustMapFitOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  FLEETLOC_RETURN_IF_ERROR(CheckMapFitInputs(landmarks, points, weights, initial));
  const double final_radius = options.final_radius_m;
  Problem problem{LandmarksNear(landmarks, points, initial, options.search_radius_m + final_radius),
                  points,
                  weights,
                  BoxOf(points),
                  final_radius,
                  options};
  if (problem.landmarks.empty()) {
    MapFitResult result;
    result.correction = initial;
    result.starts = 0;
    result.reason =
        "no landmark within the search radius " + Num(options.search_radius_m) + " m of the points";
    return result;
  }
  const std::vector<Mode> modes = RefineStarts(problem, initial);
  MapFitResult result = ChooseMode(modes, problem, initial);
  result.starts = static_cast<int>(modes.size());
  return result;
}

}  // namespace fleetloc::mapmatch
