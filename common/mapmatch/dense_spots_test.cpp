// Dense spots: tight clusters among uniform outliers come out first, at their centres, with their
// sizes as support; weights count; the number of spots is bounded.
#include "mapmatch/dense_spots.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace fleetloc::mapmatch {
namespace {

// Clusters of σ = 1 cm at `centers` (sizes `sizes`) and `outliers` uniform points over 6 m × 6 m.
std::vector<Eigen::Vector2d> Clusters(const std::vector<Eigen::Vector2d>& centers,
                                      const std::vector<int>& sizes, int outliers,
                                      std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> uniform(0.0, 6.0);
  std::vector<Eigen::Vector2d> points;
  for (std::size_t c = 0; c < centers.size(); ++c)
    for (int k = 0; k < sizes[c]; ++k)
      points.push_back(centers[c] + Eigen::Vector2d(noise(rng), noise(rng)));
  for (int k = 0; k < outliers; ++k) points.emplace_back(uniform(rng), uniform(rng));
  std::shuffle(points.begin(), points.end(), rng);
  return points;
}

TEST(DenseSpots, TightClustersComeFirstAtTheirCentres) {
  const std::vector<Eigen::Vector2d> centers{{1, 1}, {4, 2}, {2.5, 5}};
  const std::vector<int> sizes{12, 9, 6};
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    const std::vector<Eigen::Vector2d> points = Clusters(centers, sizes, 250, rng);  // 90 %
    const std::vector<DenseSpot> spots = FindDenseSpots(points, {}, 0.03, 16);
    ASSERT_EQ(spots.size(), 16u);
    for (std::size_t c = 0; c < centers.size(); ++c) {
      // σ/√n ≈ 3–4 mm for the mean; the mode of 6–12 points seen through a 3 cm window wanders
      // more (measured up to 11 mm over these seeds).
      EXPECT_LT((spots[c].center - centers[c]).norm(), 0.015) << "seed " << seed;
      EXPECT_GE(spots[c].support, sizes[c] - 2) << "seed " << seed;
      EXPECT_LE(spots[c].support, sizes[c] + 2) << "seed " << seed;
    }
    EXPECT_LE(spots[3].support, 3) << "outliers seldom meet within 3 cm";
    for (std::size_t a = 0; a < spots.size(); ++a)
      for (std::size_t b = a + 1; b < spots.size(); ++b)
        EXPECT_GE((spots[a].center - spots[b].center).norm(), 0.03);
  }
}

TEST(DenseSpots, WeightsCountAndWeightlessPointsDoNotStartSpots) {
  const std::vector<Eigen::Vector2d> points{{0, 0}, {0.01, 0}, {1, 1}, {1.01, 1}, {3, 3}};
  const std::vector<double> weights{1.0, 1.0, 5.0, 5.0, 0.0};
  const std::vector<DenseSpot> spots = FindDenseSpots(points, weights, 0.05, 10);
  ASSERT_EQ(spots.size(), 2u) << "the weightless point is no spot";
  EXPECT_NEAR(spots[0].center.x(), 1.005, 1e-12);
  EXPECT_DOUBLE_EQ(spots[0].support, 10.0);
  EXPECT_NEAR(spots[1].center.x(), 0.005, 1e-12);
  EXPECT_DOUBLE_EQ(spots[1].support, 2.0);
}

TEST(DenseSpots, AtMostMaxSpots) {
  std::mt19937 rng(1);
  const std::vector<Eigen::Vector2d> points = Clusters({}, {}, 100, rng);
  EXPECT_EQ(FindDenseSpots(points, {}, 0.03, 7).size(), 7u);
  EXPECT_TRUE(FindDenseSpots(points, {}, 0.03, 0).empty());
  EXPECT_TRUE(FindDenseSpots({}, {}, 0.03, 5).empty());
}

}  // namespace
}  // namespace fleetloc::mapmatch
