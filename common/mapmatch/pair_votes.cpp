// Pair votes for starting corrections (see pair_votes.h).
#include "mapmatch/pair_votes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "base/status.h"

namespace fleetloc::mapmatch {
namespace {

// For each spot, the landmarks within `reach` of it (the search radius grown by the tolerance),
// at most `most` of them, the nearest.
std::vector<std::vector<int>> Candidates(std::span<const DenseSpot> spots,
                                         std::span<const Eigen::Vector2d> landmarks, double reach,
                                         int most) {
  std::vector<std::vector<int>> candidates(spots.size());
  std::vector<std::pair<double, int>> within;
  for (std::size_t k = 0; k < spots.size(); ++k) {
    within.clear();
    for (std::size_t m = 0; m < landmarks.size(); ++m) {
      const double d2 = (landmarks[m] - spots[k].center).squaredNorm();
      if (d2 < reach * reach) within.emplace_back(d2, static_cast<int>(m));
    }
    if (static_cast<int>(within.size()) > most) {
      std::nth_element(within.begin(), within.begin() + most, within.end());
      within.resize(most);
    }
    for (const auto& [d2, m] : within) candidates[k].push_back(m);
  }
  return candidates;
}

struct Voting {
  std::span<const DenseSpot> spots;
  std::span<const Eigen::Vector2d> landmarks;
  std::vector<std::vector<int>> candidates;
  const PairVoteOptions& options;
};

double Score(const Voting& v, const geometry::Pose2& correction) {
  const double t2 = v.options.tolerance_m * v.options.tolerance_m;
  double score = 0.0;
  for (std::size_t k = 0; k < v.spots.size(); ++k) {
    const Eigen::Vector2d moved = correction * v.spots[k].center;
    double best = t2;
    for (const int m : v.candidates[k])
      best = std::min(best, (v.landmarks[m] - moved).squaredNorm());
    score += v.spots[k].support * (1.0 - best / t2);
  }
  return score;
}

// Every proposal of the spot pair (k, l): each landmark pair at their distance.
void VotePair(const Voting& v, std::size_t k, std::size_t l, std::vector<VotedCorrection>* out) {
  const Eigen::Vector2d& a = v.spots[k].center;
  const Eigen::Vector2d& b = v.spots[l].center;
  const double distance = (b - a).norm();
  if (distance < v.options.min_pair_distance_m) return;
  for (const int i : v.candidates[k]) {
    for (const int j : v.candidates[l]) {
      if (i == j) continue;
      const Eigen::Vector2d& m_a = v.landmarks[i];
      const Eigen::Vector2d& m_b = v.landmarks[j];
      if (std::abs((m_b - m_a).norm() - distance) > v.options.tolerance_m) continue;
      const geometry::Pose2 correction = RigidFromTwoPairs(a, b, m_a, m_b);
      out->push_back({correction, Score(v, correction)});
    }
  }
}

// The extent of the spots: distinct proposals must disagree somewhere in it.
void SpotBox(std::span<const DenseSpot> spots, Eigen::Vector2d* low, Eigen::Vector2d* high) {
  *low = spots.front().center;
  *high = *low;
  for (const DenseSpot& s : spots) {
    *low = low->cwiseMin(s.center);
    *high = high->cwiseMax(s.center);
  }
}

}  // namespace

geometry::Pose2 RigidFromTwoPairs(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                  const Eigen::Vector2d& m_a, const Eigen::Vector2d& m_b) {
  const Eigen::Vector2d from = b - a, to = m_b - m_a;
  const double theta = std::atan2(from.x() * to.y() - from.y() * to.x(), from.dot(to));
  const Eigen::Vector2d shift = 0.5 * (m_a + m_b) - Eigen::Rotation2Dd(theta) * (0.5 * (a + b));
  return {shift.x(), shift.y(), theta};
}

double LargestDisagreement(const geometry::Pose2& a, const geometry::Pose2& b,
                           const Eigen::Vector2d& low, const Eigen::Vector2d& high) {
  double largest = 0.0;
  for (const Eigen::Vector2d& corner :
       {low, high, Eigen::Vector2d(low.x(), high.y()), Eigen::Vector2d(high.x(), low.y())})
    largest = std::max(largest, (a * corner - b * corner).norm());
  return largest;
}

std::vector<VotedCorrection> VoteCorrections(std::span<const DenseSpot> spots,
                                             std::span<const Eigen::Vector2d> landmarks,
                                             const PairVoteOptions& options) {
  FLEETLOC_CHECK(options.search_radius_m > 0 && options.tolerance_m > 0 &&
                 options.min_pair_distance_m >= 0 && options.max_corrections > 0 &&
                 options.max_landmarks_per_spot > 0);
  if (spots.size() < 2 || landmarks.size() < 2) return {};
  const Voting voting{spots, landmarks,
                      Candidates(spots, landmarks, options.search_radius_m + options.tolerance_m,
                                 options.max_landmarks_per_spot),
                      options};
  std::vector<VotedCorrection> proposals;
  for (std::size_t k = 0; k < spots.size(); ++k)
    for (std::size_t l = k + 1; l < spots.size(); ++l) VotePair(voting, k, l, &proposals);
  std::stable_sort(
      proposals.begin(), proposals.end(),
      [](const VotedCorrection& a, const VotedCorrection& b) { return a.score > b.score; });
  Eigen::Vector2d low, high;
  SpotBox(spots, &low, &high);
  std::vector<VotedCorrection> distinct;
  for (const VotedCorrection& p : proposals) {
    if (static_cast<int>(distinct.size()) >= options.max_corrections) break;
    const bool known = std::any_of(distinct.begin(), distinct.end(), [&](const auto& d) {
      return LargestDisagreement(d.correction, p.correction, low, high) < options.tolerance_m;
    });
    if (!known) distinct.push_back(p);
  }
  return distinct;
}

}  // namespace fleetloc::mapmatch
