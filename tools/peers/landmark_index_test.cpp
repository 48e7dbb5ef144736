// The landmark grid and the pair-distance table give what brute force gives (landmark_index.h),
// on landmarks clustered like room corners (twins a few centimetres apart) and on queries all
// around them, near and far.
#include "peers/landmark_index.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace fleetloc::peers {
namespace {

// 40 landmarks: 20 spread over 12 m × 8 m, each with a twin 2–30 cm away.
std::vector<Eigen::Vector2d> Landmarks(std::mt19937& rng) {
  std::uniform_real_distribution<double> x(0, 12), y(0, 8), near(-0.2, 0.2);
  std::vector<Eigen::Vector2d> landmarks;
  for (int k = 0; k < 20; ++k) {
    landmarks.emplace_back(x(rng), y(rng));
    const Eigen::Vector2d twin = landmarks.back() + Eigen::Vector2d(near(rng), near(rng));
    landmarks.push_back(twin);  // not emplace_back: the argument reads landmarks.back()
  }
  return landmarks;
}

int BruteNearestWithin(const std::vector<Eigen::Vector2d>& landmarks, const Eigen::Vector2d& xy,
                       double reach) {
  int best = -1;
  double best_d = reach;
  for (std::size_t m = 0; m < landmarks.size(); ++m) {
    if ((landmarks[m] - xy).norm() <= best_d) {
      best_d = (landmarks[m] - xy).norm();
      best = int(m);
    }
  }
  return best;
}

TEST(LandmarkGrid, NearestWithinReachIsTheBruteForceAnswer) {
  std::mt19937 rng(7);
  const std::vector<Eigen::Vector2d> landmarks = Landmarks(rng);
  std::uniform_real_distribution<double> x(-3, 15), y(-3, 11);
  for (const double reach : {0.03, 0.1, 0.5}) {
    const LandmarkGrid grid(landmarks, reach);
    std::uniform_real_distribution<double> near(-reach, reach);
    int found = 0;
    for (int q = 0; q < 4000; ++q) {
      // Half the queries within a square of side 2 × reach around a landmark (78 % of them
      // within reach), half anywhere, also outside the landmarks' extent.
      const Eigen::Vector2d xy =
          q % 2 ? landmarks[q % landmarks.size()] + Eigen::Vector2d(near(rng), near(rng))
                : Eigen::Vector2d(x(rng), y(rng));
      const int expected = BruteNearestWithin(landmarks, xy, reach);
      ASSERT_EQ(grid.NearestWithin(xy), expected) << "reach " << reach << ", query " << q;
      found += expected >= 0;
    }
    EXPECT_GT(found, 1500) << "the near queries find their landmark";
  }
  EXPECT_EQ(LandmarkGrid(landmarks, 0.03).NearestWithin({1e12, -1e12}), -1);
}

TEST(LandmarkPairTable, MatchingIsEveryPairOfThatLength) {
  std::mt19937 rng(8);
  const std::vector<Eigen::Vector2d> landmarks = Landmarks(rng);
  const LandmarkPairTable table(landmarks);
  for (const double distance : {0.1, 1.0, 3.7, 9.0, 20.0}) {
    int expected = 0;
    for (std::size_t a = 0; a < landmarks.size(); ++a)
      for (std::size_t b = a + 1; b < landmarks.size(); ++b)
        expected += std::abs((landmarks[a] - landmarks[b]).norm() - distance) <= 0.06;
    int got = 0;
    for (const LandmarkPair& p : table.Matching(distance, 0.06)) {
      EXPECT_LT(p.a, p.b);
      EXPECT_NEAR((landmarks[p.a] - landmarks[p.b]).norm(), p.distance_m, 1e-12);
      EXPECT_LE(std::abs(p.distance_m - distance), 0.06);
      ++got;
    }
    EXPECT_EQ(got, expected) << "distance " << distance;
  }
  EXPECT_TRUE(table.Matching(100.0, 0.06).empty());
}

}  // namespace
}  // namespace fleetloc::peers
