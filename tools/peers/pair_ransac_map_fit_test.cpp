// The correspondence-free RANSAC peer solves cluttered room problems whose start is up to a metre
// off (about the map origin), where the nearest-landmark RANSAC pairs points with the wrong
// landmarks and fails; clean points give the truth; no matching pair is a refusal.
#include "peers/pair_ransac_map_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "mapmatch/room_map_problem.h"
#include "peers/map_fit_peers.h"

namespace fleetloc::peers {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The bench's success criterion: within 1 cm and 0.5° at the vehicle.
bool Succeeds(const mapmatch::MapFitResult& fit, const mapmatch::RoomProblem& room) {
  const geometry::Pose2& truth = room.problem.truth;
  const double position = (fit.correction * room.vehicle - truth * room.vehicle).norm();
  const double rotation = std::abs(geometry::WrapAngle(fit.correction.theta - truth.theta));
  return fit.converged && position < 0.01 && rotation < 0.5 * kDeg;
}

struct Successes {
  int with_hint = 0;     // the pair RANSAC searching within the radius hint (as in the bench)
  int without_hint = 0;  // the pair RANSAC pairing points with any landmark
  int nearest = 0;       // the nearest-landmark RANSAC (RANSAC-NN)
};

// 20 room problems (30 landmarks, the estimate up to 0.3 m and 10° off, half the outliers in
// clusters like landmarks), every fit from the drifted estimate.
Successes SolveRooms(unsigned seed, double outlier_fraction) {
  std::mt19937 rng(seed);
  Successes successes;
  for (int trial = 0; trial < 20; ++trial) {
    const mapmatch::RoomMap map = mapmatch::BuildRoomMap(30, rng);
    const mapmatch::RoomProblem room =
        mapmatch::SimulateRoomProblem(map, {.outlier_fraction = outlier_fraction}, rng);
    const std::vector<Eigen::Vector2d>& points = room.problem.points;
    successes.with_hint += Succeeds(
        PairRansacMapFit(map.landmarks, points, {}, {.search_radius_m = room.radius_hint_m}), room);
    successes.without_hint += Succeeds(PairRansacMapFit(map.landmarks, points, {}), room);
    successes.nearest += Succeeds(NearestRansacMapFit(map.landmarks, points, {}), room);
  }
  return successes;
}

TEST(PairRansacMapFit, RoomsAtSeventyPercentOutliersWhereNearestLandmarkRansacFails) {
  const Successes successes = SolveRooms(70, 0.7);
  EXPECT_EQ(successes.with_hint, 20);
  // Without the prior, a clutter cluster or a corner's twin across a wall wins the inlier count
  // on some problems.
  EXPECT_EQ(successes.without_hint, 13);
  EXPECT_EQ(successes.nearest, 5);
}

TEST(PairRansacMapFit, RoomsAtNinetyPercentOutliers) {
  const Successes successes = SolveRooms(90, 0.9);
  EXPECT_EQ(successes.with_hint, 20);
  EXPECT_EQ(successes.without_hint, 15);
  EXPECT_EQ(successes.nearest, 0);
}

TEST(PairRansacMapFit, CleanPointsGiveTheTruth) {
  std::mt19937 rng(3);
  const mapmatch::RoomMap map = mapmatch::BuildRoomMap(30, rng);
  const mapmatch::RoomProblem room =
      mapmatch::SimulateRoomProblem(map, {.noise_sigma_m = 0.0, .outlier_fraction = 0.0}, rng);
  const mapmatch::MapFitResult fit = PairRansacMapFit(map.landmarks, room.problem.points, {},
                                                      {.search_radius_m = room.radius_hint_m});
  ASSERT_TRUE(fit.converged) << fit.reason;
  EXPECT_EQ(fit.inliers, room.problem.inliers);
  EXPECT_EQ(fit.landmarks_matched, static_cast<int>(room.seen.size()));
  EXPECT_LT(mapmatch::ErrorOf(fit.correction, room.problem.truth).translation_m, 1e-9);
  EXPECT_LT(mapmatch::ErrorOf(fit.correction, room.problem.truth).rotation_rad, 1e-9);
  EXPECT_LT(fit.rms_residual_m, 1e-9);
}

// Points all within 10 cm of each other: no pair is long enough to fix the rotation.
TEST(PairRansacMapFit, NoMatchingPairIsARefusal) {
  const std::vector<Eigen::Vector2d> landmarks{{0, 0}, {3, 0}, {3, 2}};
  const std::vector<Eigen::Vector2d> points{{0.01, 0}, {0.05, 0.02}, {0.08, 0.09}, {0.0, 0.1}};
  const geometry::Pose2 initial{0.2, -0.1, 0.05};
  const mapmatch::MapFitResult fit = PairRansacMapFit(landmarks, points, initial);
  EXPECT_FALSE(fit.converged);
  EXPECT_EQ(fit.iterations, 0);
  EXPECT_EQ(fit.reason, "RANSAC: no point pair matches a landmark pair");
  EXPECT_EQ(fit.correction.x, initial.x);
  EXPECT_EQ(fit.correction.theta, initial.theta);
}

}  // namespace
}  // namespace fleetloc::peers
