// Pair votes: spots that are landmarks seen through a correction vote that correction, best
// first and once; a spot beyond the search radius of every landmark does not vote; the two-pair
// rigid transform is exact and the disagreement of two corrections is measured at the box.
#include "mapmatch/pair_votes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace fleetloc::mapmatch {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A room's corners and a door's jambs (metres).
const std::vector<Eigen::Vector2d> kMap{{0, 0}, {4, 0}, {4, 3}, {0, 3}, {1.5, 3}, {2.4, 3}};

std::vector<DenseSpot> SpotsSeenThrough(const geometry::Pose2& correction,
                                        const std::vector<int>& seen) {
  std::vector<DenseSpot> spots;
  for (const int m : seen) spots.push_back({correction.Inverse() * kMap[m], 10.0});
  return spots;
}

TEST(PairVotes, SpotsOnLandmarksVoteTheCorrection) {
  const geometry::Pose2 truth{0.2, -0.3, 6 * kDeg};
  const std::vector<DenseSpot> spots = SpotsSeenThrough(truth, {0, 1, 2, 4});
  const std::vector<VotedCorrection> voted =
      VoteCorrections(spots, kMap, {.search_radius_m = 0.6, .tolerance_m = 0.03});
  ASSERT_FALSE(voted.empty());
  EXPECT_NEAR(voted[0].correction.x, truth.x, 1e-9);
  EXPECT_NEAR(voted[0].correction.y, truth.y, 1e-9);
  EXPECT_NEAR(voted[0].correction.theta, truth.theta, 1e-9);
  EXPECT_NEAR(voted[0].score, 40.0, 1e-6) << "all four spots on their landmarks";
  for (std::size_t k = 1; k < voted.size(); ++k) {
    EXPECT_LT(voted[k].score, voted[0].score);
    EXPECT_GT(LargestDisagreement(voted[k].correction, voted[0].correction, {0, 0}, {4, 3}), 0.03)
        << "each proposal once";
  }
}

TEST(PairVotes, OnlyLandmarksWithinTheSearchRadiusArePaired) {
  const geometry::Pose2 truth{0.5, 0.0, 0.0};  // moves every spot 0.5 m
  const std::vector<DenseSpot> spots = SpotsSeenThrough(truth, {0, 1, 2});
  EXPECT_TRUE(VoteCorrections(spots, kMap, {.search_radius_m = 0.3, .tolerance_m = 0.03}).empty());
  EXPECT_FALSE(VoteCorrections(spots, kMap, {.search_radius_m = 0.6, .tolerance_m = 0.03}).empty());
}

TEST(PairVotes, AtMostMaxCorrectionsAndCloseSpotsDoNotVote) {
  const std::vector<DenseSpot> spots = SpotsSeenThrough({}, {0, 1, 2, 3, 4, 5});
  EXPECT_LE(VoteCorrections(spots, kMap, {.search_radius_m = 5, .max_corrections = 3}).size(), 3u);
  const std::vector<DenseSpot> close{{{0, 0}, 5.0}, {{0.1, 0}, 5.0}};
  const std::vector<Eigen::Vector2d> close_map{{0, 0}, {0.1, 0}};
  EXPECT_TRUE(VoteCorrections(close, close_map, {.search_radius_m = 1}).empty())
      << "10 cm apart: closer than min_pair_distance_m";
}

// 20,000 landmarks scattered over 100 m × 100 m and a search radius covering all of them: each
// spot pairs only with its 24 nearest, which still hold the right ones.
TEST(PairVotes, AWideSearchOverALargeMapPairsSpotsWithTheirNearestLandmarks) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 100.0);
  std::vector<Eigen::Vector2d> map{{50, 50}, {53, 50}, {50, 52}};
  for (int k = 0; k < 20000; ++k) map.emplace_back(uniform(rng), uniform(rng));
  const geometry::Pose2 truth{0.1, -0.05, 0.5 * kDeg};
  std::vector<DenseSpot> spots;
  for (int m = 0; m < 3; ++m) spots.push_back({truth.Inverse() * map[m], 10.0});
  const std::vector<VotedCorrection> voted =
      VoteCorrections(spots, map, {.search_radius_m = 200, .tolerance_m = 0.03});
  ASSERT_FALSE(voted.empty());
  EXPECT_LT(LargestDisagreement(voted[0].correction, truth, {49, 49}, {54, 53}), 1e-9);
}

TEST(PairVotes, RigidFromTwoPairsIsExact) {
  const geometry::Pose2 t{1.0, -2.0, 30 * kDeg};
  const Eigen::Vector2d a(0.3, 0.7), b(-2.0, 1.5);
  const geometry::Pose2 r = RigidFromTwoPairs(a, b, t * a, t * b);
  EXPECT_NEAR(r.x, t.x, 1e-12);
  EXPECT_NEAR(r.y, t.y, 1e-12);
  EXPECT_NEAR(r.theta, t.theta, 1e-12);
}

TEST(PairVotes, LargestDisagreementIsAtTheFarthestCorner) {
  const geometry::Pose2 turned{0, 0, 0.01};
  // A turn about the origin moves the corner (4, 3) most: 5 m × 0.01 rad.
  EXPECT_NEAR(LargestDisagreement({}, turned, {0, 0}, {4, 3}), 5 * 2 * std::sin(0.005), 1e-12);
  EXPECT_NEAR(LargestDisagreement({}, {0.1, 0, 0}, {0, 0}, {4, 3}), 0.1, 1e-12);
}

}  // namespace
}  // namespace fleetloc::mapmatch
