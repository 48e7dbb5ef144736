// Global vote for starting corrections of the map fit: every two dense spots (dense_spots.h)
// whose distance matches the distance of two landmarks, each landmark within the search radius of
// its spot, propose the rigid correction that puts the spots on the landmarks. Each proposal is
// scored by the spots it puts on a landmark within their search radius, weighted by their support;
// the best distinct proposals start the mean-shift fit (robust_map_fit.h). The search radius
// bounds how far the correction may move a spot, not the rotation.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "geometry/pose2.h"
#include "mapmatch/dense_spots.h"

namespace fleetloc::mapmatch {

struct PairVoteOptions {
  double search_radius_m = 0.0;  // a spot may land on a landmark this far from it; > 0
  // Two distances agree, and a spot lands on a landmark, within this; it also sets how far apart
  // two proposals must put some spot to count as distinct; > 0.
  double tolerance_m = 0.05;
  double min_pair_distance_m = 0.2;  // spots closer than this do not vote (rotation too loose)
  int max_corrections = 8;           // > 0
  // A spot pairs with at most this many landmarks within reach, the nearest: bounds the cost of a
  // wide search over a large map (spots² × this² distance checks); > 0.
  int max_landmarks_per_spot = 24;
};

struct VotedCorrection {
  geometry::Pose2 correction;  // moves the spots onto the landmarks
  // Σ support × (1 − d²/tolerance²) over the spots within tolerance of a landmark (d: that
  // distance), each spot counted once.
  double score = 0.0;
};

// At most max_corrections distinct proposals, best score first; empty when no two spots match two
// landmarks. Requires finite inputs and options in range (checked: aborts otherwise).
std::vector<VotedCorrection> VoteCorrections(std::span<const DenseSpot> spots,
                                             std::span<const Eigen::Vector2d> landmarks,
                                             const PairVoteOptions& options);

// The rigid transform moving a onto m_a and b onto m_b as well as the two allow: the rotation of
// b − a onto m_b − m_a, the midpoints on each other.
geometry::Pose2 RigidFromTwoPairs(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                  const Eigen::Vector2d& m_a, const Eigen::Vector2d& m_b);

// The largest distance by which `a` and `b` place any corner of the box [low, high] (the extent of
// the points they act on): how different two corrections are where it matters.
double LargestDisagreement(const geometry::Pose2& a, const geometry::Pose2& b,
                           const Eigen::Vector2d& low, const Eigen::Vector2d& high);

}  // namespace fleetloc::mapmatch
