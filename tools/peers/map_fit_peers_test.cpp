// The map-fit peers recover a known correction from clean points, so the benchmark compares
// working implementations; ICP's lack of outlier rejection shows with outliers.
#include "peers/map_fit_peers.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "mapmatch/map_fit_problem.h"

namespace fleetloc::peers {
namespace {

const std::vector<Eigen::Vector2d> kMap{{0, 0}, {4, 0}, {4, 3}, {0, 3}, {8, 0}, {8, 3}};
const std::vector<int> kObserved{0, 1, 2, 3};
const geometry::Pose2 kTruth{0.05, -0.03, 0.02};

mapmatch::MapFitProblem Problem(double outlier_fraction) {
  std::mt19937 rng(4);
  return mapmatch::SimulateMapFitProblem(
      kMap, kObserved, kTruth, {.noise_sigma_m = 0.0, .outlier_fraction = outlier_fraction}, rng);
}

TEST(MapFitPeers, CleanPointsGiveTheTruth) {
  const mapmatch::MapFitProblem clean = Problem(0.0);
  for (const mapmatch::MapFitResult& fit :
       {NearestRansacMapFit(kMap, clean.points, {}), IcpMapFit(kMap, clean.points, {})}) {
    ASSERT_TRUE(fit.converged) << fit.reason;
    EXPECT_LT(mapmatch::ErrorOf(fit.correction, kTruth).translation_m, 1e-6);
    EXPECT_LT(mapmatch::ErrorOf(fit.correction, kTruth).rotation_rad, 1e-6);
  }
}

TEST(MapFitPeers, RansacRejectsOutliersAndIcpDoesNot) {
  const mapmatch::MapFitProblem noisy = Problem(0.5);
  const mapmatch::MapFitResult ransac = NearestRansacMapFit(kMap, noisy.points, {});
  ASSERT_TRUE(ransac.converged);
  EXPECT_LT(mapmatch::ErrorOf(ransac.correction, kTruth).translation_m, 1e-3);
  EXPECT_EQ(ransac.inliers, noisy.inliers);
  const mapmatch::MapFitResult icp = IcpMapFit(kMap, noisy.points, {});
  EXPECT_GT(mapmatch::ErrorOf(icp.correction, kTruth).translation_m, 0.01);
}

}  // namespace
}  // namespace fleetloc::peers
