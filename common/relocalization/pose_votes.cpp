// Pose votes, their clustering and the rigid fit of a cluster (see pose_votes.h).
#include "relocalization/pose_votes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "mapmatch/mean_shift.h"

namespace fleetloc::relocalization {
namespace {

struct Vote {
  Eigen::Vector2d position_m;
  double heading_rad = 0.0;
};

using CellKey = std::tuple<long, long, int>;

// Hough cells (radius × radius × heading tolerance) ordered by their vote count, most first.
std::vector<std::vector<int>> CellsByCount(const std::vector<Vote>& votes,
                                           const VoteClusterOptions& options) {
  std::map<CellKey, std::vector<int>> cells;
  for (std::size_t i = 0; i < votes.size(); ++i) {
    const Vote& v = votes[i];
    cells[{std::lround(std::floor(v.position_m.x() / options.radius_m)),
           std::lround(std::floor(v.position_m.y() / options.radius_m)),
           static_cast<int>(std::floor((v.heading_rad + M_PI) / options.heading_tolerance_rad))}]
        .push_back(static_cast<int>(i));
  }
  std::vector<std::vector<int>> ordered;
  ordered.reserve(cells.size());
  for (auto& [key, members] : cells) ordered.push_back(std::move(members));
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return ordered;
}

// Circular mean of the votes' headings.
double MeanHeading(const std::vector<Vote>& votes, const std::vector<int>& members) {
  double s = 0, c = 0;
  for (int i : members) s += std::sin(votes[i].heading_rad), c += std::cos(votes[i].heading_rad);
  return std::atan2(s, c);
}

// The matches whose frame feature lands within `distance` of its map feature under `pose`, one
// per frame feature (the closest).
std::vector<FeatureMatch> Inliers(const std::vector<FeatureMatch>& matches,
                                  const geometry::Pose2& pose, double distance, double* rms) {
  std::map<int, std::pair<double, int>> best;  // query → (error², match)
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const double e2 = (pose * matches[i].ground_m - matches[i].map_m).squaredNorm();
    if (e2 > distance * distance) continue;
    auto [it, inserted] = best.try_emplace(matches[i].query, e2, static_cast<int>(i));
    if (!inserted && e2 < it->second.first) it->second = {e2, static_cast<int>(i)};
  }
  std::vector<FeatureMatch> inliers;
  double sum = 0;
  for (const auto& [query, entry] : best)
    sum += entry.first, inliers.push_back(matches[entry.second]);
  *rms = inliers.empty() ? 0.0 : std::sqrt(sum / inliers.size());
  return inliers;
}

bool NearAny(const std::vector<PoseCandidate>& found, const geometry::Pose2& pose,
             const VoteClusterOptions& options) {
  return std::any_of(found.begin(), found.end(), [&](const PoseCandidate& c) {
    return std::hypot(c.camera_in_map.x - pose.x, c.camera_in_map.y - pose.y) < options.radius_m &&
           std::abs(geometry::WrapAngle(c.camera_in_map.theta - pose.theta)) <
               options.heading_tolerance_rad;
  });
}

// One candidate grown from a seed cell: heading-consistent votes, mean shift from the cell's
// centre, rigid fit of the cluster, then inliers among all matches and a refit.
std::optional<PoseCandidate> GrowCandidate(const std::vector<FeatureMatch>& matches,
                                           const std::vector<Vote>& votes,
                                           const std::vector<int>& seed,
                                           const VoteClusterOptions& options) {
  const double heading = MeanHeading(votes, seed);
  std::vector<int> consistent;
  std::vector<Eigen::Vector2d> positions;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  for (int i : seed) start += votes[i].position_m / static_cast<double>(seed.size());
  for (std::size_t i = 0; i < votes.size(); ++i) {
    if (std::abs(geometry::WrapAngle(votes[i].heading_rad - heading)) >=
        options.heading_tolerance_rad)
      continue;
    consistent.push_back(static_cast<int>(i));
    positions.push_back(votes[i].position_m);
  }
  const Result<mapmatch::MeanShiftResult> mode = mapmatch::MeanShiftMode(
      positions, {}, start, mapmatch::MeanShiftOptions{.radius = options.radius_m});
  if (!mode.ok() || mode->support < options.min_support) return std::nullopt;
  std::vector<FeatureMatch> cluster;
  for (std::size_t j = 0; j < consistent.size(); ++j) {
    if ((positions[j] - mode->mode).norm() < options.radius_m)
      cluster.push_back(matches[consistent[j]]);
  }
  PoseCandidate candidate;
  candidate.support = static_cast<int>(cluster.size());
  candidate.camera_in_map = FitRigid(cluster);
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<FeatureMatch> inliers =
        Inliers(matches, candidate.camera_in_map, options.inlier_distance_m, &candidate.rms_m);
    candidate.inliers = static_cast<int>(inliers.size());
    if (candidate.inliers < 2) return std::nullopt;
    candidate.camera_in_map = FitRigid(inliers);
  }
  return candidate;
}

}  // namespace

Status Validate(const VoteClusterOptions& options) {
  if (!(options.radius_m > 0.0 && options.radius_m < 10.0))
    return InvalidInput("vote clustering: radius_m must be in (0, 10)");
  if (!(options.heading_tolerance_rad > 0.0 && options.heading_tolerance_rad <= M_PI / 2))
    return InvalidInput("vote clustering: heading_tolerance_rad must be in (0, pi/2]");
  if (options.max_candidates < 1)
    return InvalidInput("vote clustering: max_candidates must be >= 1");
  if (options.min_support < 2) return InvalidInput("vote clustering: min_support must be >= 2");
  if (!(options.inlier_distance_m > 0.0 && options.inlier_distance_m <= options.radius_m))
    return InvalidInput("vote clustering: inlier_distance_m must be in (0, radius_m]");
  return Status::Ok();
}

geometry::Pose2 VotedPose(const FeatureMatch& match) {
  const double heading = geometry::WrapAngle(match.map_heading_rad - match.ground_heading_rad);
  const Eigen::Vector2d position = match.map_m - Eigen::Rotation2Dd(heading) * match.ground_m;
  return {position.x(), position.y(), heading};
}

geometry::Pose2 FitRigid(const std::vector<FeatureMatch>& matches) {
  FLEETLOC_CHECK(matches.size() >= 2);
  Eigen::Vector2d ground_mean = Eigen::Vector2d::Zero(), map_mean = Eigen::Vector2d::Zero();
  for (const FeatureMatch& m : matches) ground_mean += m.ground_m, map_mean += m.map_m;
  ground_mean /= static_cast<double>(matches.size());
  map_mean /= static_cast<double>(matches.size());
  double dot = 0, cross = 0;
  for (const FeatureMatch& m : matches) {
    const Eigen::Vector2d g = m.ground_m - ground_mean, p = m.map_m - map_mean;
    dot += g.dot(p);
    cross += g.x() * p.y() - g.y() * p.x();
  }
  const double theta = std::atan2(cross, dot);
  const Eigen::Vector2d t = map_mean - Eigen::Rotation2Dd(theta) * ground_mean;
  return {t.x(), t.y(), theta};
}

std::vector<PoseCandidate> ClusterVotes(const std::vector<FeatureMatch>& matches,
                                        const VoteClusterOptions& options) {
  std::vector<Vote> votes;
  for (const FeatureMatch& m : matches) {
    const geometry::Pose2 pose = VotedPose(m);
    votes.push_back({{pose.x, pose.y}, pose.theta});
  }
  std::vector<PoseCandidate> found;
  const int max_seeds = 4 * options.max_candidates;
  int seeds = 0;
  for (const std::vector<int>& cell : CellsByCount(votes, options)) {
    if (static_cast<int>(found.size()) >= options.max_candidates || seeds++ >= max_seeds) break;
    if (static_cast<int>(cell.size()) * 4 < options.min_support) break;  // sparser cells follow
    std::optional<PoseCandidate> candidate = GrowCandidate(matches, votes, cell, options);
    if (!candidate || candidate->inliers < options.min_support ||
        NearAny(found, candidate->camera_in_map, options))
      continue;
    found.push_back(*candidate);
  }
  std::sort(found.begin(), found.end(),
            [](const PoseCandidate& a, const PoseCandidate& b) { return a.inliers > b.inliers; });
  return found;
}

}  // namespace fleetloc::relocalization
