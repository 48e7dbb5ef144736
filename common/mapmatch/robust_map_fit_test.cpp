// The robust map fit (issue 16): rooms seen through clustered clutter that the mean shift from the
// start with h = the hint gets confidently wrong; the paper's figure 3; lone stray points that
// neither pull nor count; two readings supported alike reported as ambiguous; points that land on
// no landmark refused with the reason; bad options and inputs.
#include "mapmatch/robust_map_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mapmatch/map_fit_problem.h"
#include "mapmatch/room_map_problem.h"

namespace fleetloc::mapmatch {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct VehicleError {
  double position_m = 0.0;
  double rotation_rad = 0.0;
};

VehicleError ErrorAtVehicle(const geometry::Pose2& fit, const RoomProblem& room) {
  const geometry::Pose2& truth = room.problem.truth;
  return {(fit * room.vehicle - truth * room.vehicle).norm(),
          std::abs(geometry::WrapAngle(fit.theta - truth.theta))};
}

// 80 % outliers, half of them clusters like landmarks; the estimate up to 0.3 m and 10° off;
// --radius a hint 1–3× the largest displacement.
TEST(RobustMapFit, RoomsSeenThroughClutterAreFittedWhereTheLocalFitIsConfidentlyWrong) {
  std::mt19937 rng(1616);
  int local_wrong = 0, within_1cm = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const RoomMap map = BuildRoomMap(30, rng);
    const RoomProblem room = SimulateRoomProblem(map, {.outlier_fraction = 0.8}, rng);
    const std::vector<Eigen::Vector2d>& points = room.problem.points;
    // Before issue 16, `fleetctl mapmatch --radius H` was the mean shift from the start, h = H.
    const MapFitResult local =
        FitMap(map.landmarks, points, {}, {}, {.radius_m = room.radius_hint_m}).value();
    if (local.converged && ErrorAtVehicle(local.correction, room).position_m > 0.03) ++local_wrong;

    const MapFitResult fit =
        RobustFitMap(map.landmarks, points, {}, {}, {.search_radius_m = room.radius_hint_m})
            .value();
    ASSERT_TRUE(fit.converged) << "trial " << trial << ": " << fit.reason;
    EXPECT_EQ(fit.landmarks_matched, static_cast<int>(room.seen.size())) << "trial " << trial;
    EXPECT_FALSE(fit.ambiguous);
    EXPECT_GT(fit.starts, 1) << "voted starts besides the initial correction";
    // The right reading in every trial. In trial 14 the three corners seen are a door's jambs and
    // a corner on one wall, 1.3 m long, 1.9 m from the vehicle: the cluster means' noise (up to
    // 10 mm) turns the fit 0.53° and moves the vehicle 20 mm; the truth fits the points worse.
    const VehicleError error = ErrorAtVehicle(fit.correction, room);
    EXPECT_LT(error.position_m, 0.025) << "trial " << trial;
    EXPECT_LT(error.rotation_rad, 0.6 * kDeg) << "trial " << trial;
    if (error.position_m < 0.01 && error.rotation_rad < 0.5 * kDeg) ++within_1cm;
  }
  EXPECT_EQ(within_1cm, 19);
  EXPECT_GE(local_wrong, 18) << "the local fit with h = the hint, converged but centimetres off";
}

// Measured on 1000 problems per level (docs/benchmarks.md): at 90 % outliers a few are refused
// as ambiguous, about one in a thousand converges a centimetre off. Here: none wrong.
TEST(RobustMapFit, NinetyPercentOutliersAreFittedOrRefusedNeverConfidentlyWrong) {
  std::mt19937 rng(90);
  int converged = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const RoomMap map = BuildRoomMap(30, rng);
    const RoomProblem room = SimulateRoomProblem(map, {.outlier_fraction = 0.9}, rng);
    const MapFitResult fit = RobustFitMap(map.landmarks, room.problem.points, {}, {},
                                          {.search_radius_m = room.radius_hint_m})
                                 .value();
    if (!fit.converged) {
      EXPECT_FALSE(fit.reason.empty());
      EXPECT_EQ(fit.correction.ToVector(), Eigen::Vector3d::Zero()) << "the initial correction";
      continue;
    }
    ++converged;
    const VehicleError error = ErrorAtVehicle(fit.correction, room);
    EXPECT_LT(error.position_m, 0.01) << "trial " << trial;
    EXPECT_LT(error.rotation_rad, 0.5 * kDeg) << "trial " << trial;
  }
  EXPECT_GE(converged, 48);
}

// Paper figure 3: three corners, σ = 5 cm, 70 % uniform outliers, from the drifted pose.
TEST(RobustMapFit, Figure3WithAFinalRadiusOfThreeSigma) {
  const std::vector<Eigen::Vector2d> map{{0, 0}, {4, 0}, {4, 3}, {0, 3}, {8, 0}, {8, 3}};
  const std::vector<int> observed{0, 1, 2};
  const geometry::Pose2 truth{0.25, -0.15, 3.0 * kDeg};
  for (unsigned seed = 1; seed <= 50; ++seed) {
    std::mt19937 rng(seed);
    const MapFitProblem problem = SimulateMapFitProblem(
        map, observed, truth, {.noise_sigma_m = 0.05, .outlier_fraction = 0.7}, rng);
    const MapFitResult fit =
        RobustFitMap(map, problem.points, {}, {}, {.search_radius_m = 0.6, .final_radius_m = 0.15})
            .value();
    ASSERT_TRUE(fit.converged) << "seed " << seed << ": " << fit.reason;
    const CorrectionError error = ErrorOf(fit.correction, truth);
    EXPECT_LT(error.translation_m, 0.03) << "seed " << seed;  // the local fit's bounds
    EXPECT_LT(error.rotation_rad, 0.5 * kDeg) << "seed " << seed;
    EXPECT_GT(fit.covariance(2, 2), 0.0);
  }
}

// Three corners seen 10 times each (σ 5 mm); one lone point 2 cm from each of two far corners.
TEST(RobustMapFit, LoneStrayPointsNeitherPullNorCount) {
  const std::vector<Eigen::Vector2d> map{{0, 0}, {1, 0}, {0, 1}, {9, 0}, {9, 9}};
  const geometry::Pose2 truth{0.05, -0.03, 1.0 * kDeg};
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<Eigen::Vector2d> points;
  for (int m = 0; m < 3; ++m)
    for (int k = 0; k < 10; ++k)
      points.push_back(truth.Inverse() * Eigen::Vector2d(map[m] + Eigen::Vector2d(noise(rng), 0)));
  const std::vector<Eigen::Vector2d> clusters = points;
  points.push_back(truth.Inverse() * Eigen::Vector2d(9.0, 0.02));
  points.push_back(truth.Inverse() * Eigen::Vector2d(9.02, 9.0));
  const RobustMapFitOptions options{.search_radius_m = 0.2};
  const MapFitResult with = RobustFitMap(map, points, {}, {}, options).value();
  const MapFitResult without = RobustFitMap(map, clusters, {}, {}, options).value();
  ASSERT_TRUE(with.converged) << with.reason;
  ASSERT_TRUE(without.converged) << without.reason;
  EXPECT_LT(ErrorOf(with.correction, without.correction).translation_m, 1e-9);
  EXPECT_EQ(with.landmarks_matched, 3);
  EXPECT_EQ(with.inliers, 30);
  EXPECT_NEAR(with.support, without.support, 1e-9);
}

// A lattice of landmarks 1 m apart; three clusters on it; a 1.2 m search also reaches the readings
// shifted by one lattice step, which land the clusters on landmarks just as well.
TEST(RobustMapFit, TwoReadingsSupportedAlikeAreAmbiguous) {
  std::vector<Eigen::Vector2d> lattice;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) lattice.emplace_back(i, j);
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(2, 2), Eigen::Vector2d(3, 2), Eigen::Vector2d(2, 3)})
    for (int k = 0; k < 10; ++k) points.push_back(corner + Eigen::Vector2d(noise(rng), noise(rng)));
  const geometry::Pose2 start{0.1, 0.05, 0.0};
  const MapFitResult fit =
      RobustFitMap(lattice, points, {}, start, {.search_radius_m = 1.2}).value();
  EXPECT_FALSE(fit.converged);
  EXPECT_TRUE(fit.ambiguous);
  EXPECT_NE(fit.reason.find("ambiguous"), std::string::npos) << fit.reason;
  EXPECT_GE(fit.runner_up_support, 0.9 * fit.support);
  EXPECT_EQ(fit.correction.ToVector(), start.ToVector());
  // Searching only 0.3 m around the start, one reading is left.
  const MapFitResult near =
      RobustFitMap(lattice, points, {}, start, {.search_radius_m = 0.3}).value();
  ASSERT_TRUE(near.converged) << near.reason;
  EXPECT_LT(ErrorOf(near.correction, {}).translation_m, 0.005);
}

TEST(RobustMapFit, PointsThatLandOnNoLandmarkAreRefusedWithTheReason) {
  const std::vector<Eigen::Vector2d> map{{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uniform(-1.0, 5.0);
  std::vector<Eigen::Vector2d> outliers;
  for (int k = 0; k < 150; ++k) outliers.emplace_back(uniform(rng), uniform(rng));
  const geometry::Pose2 start{0.01, 0.02, 0.003};
  const MapFitResult fit = RobustFitMap(map, outliers, {}, start, {.search_radius_m = 0.5}).value();
  EXPECT_FALSE(fit.converged);
  EXPECT_FALSE(fit.reason.empty());
  EXPECT_EQ(fit.correction.ToVector(), start.ToVector());
  EXPECT_EQ(fit.covariance, Eigen::Matrix3d::Zero());

  const std::vector<Eigen::Vector2d> far{{50, 50}, {51, 50}, {50, 52}};
  const MapFitResult none = RobustFitMap(map, far, {}, {}, {.search_radius_m = 0.5}).value();
  EXPECT_FALSE(none.converged);
  EXPECT_NE(none.reason.find("no landmark within the search radius"), std::string::npos)
      << none.reason;
}

TEST(RobustMapFit, ZeroWeightPointsDoNotCount) {
  const std::vector<Eigen::Vector2d> map{{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  const geometry::Pose2 truth{0.1, 0.0, 1.0 * kDeg};
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;
  for (const Eigen::Vector2d& m : map) {
    for (int k = 0; k < 4; ++k) {
      points.push_back(truth.Inverse() * m);
      weights.push_back(1.0);
      // A heavier misplaced twin that would make another reading if it counted.
      points.push_back(truth.Inverse() * Eigen::Vector2d(m + Eigen::Vector2d(0.25, 0.1)));
      weights.push_back(0.0);
    }
  }
  const MapFitResult fit = RobustFitMap(map, points, weights, {}, {.search_radius_m = 0.5}).value();
  ASSERT_TRUE(fit.converged) << fit.reason;
  EXPECT_LT(ErrorOf(fit.correction, truth).translation_m, 1e-9);
  EXPECT_EQ(fit.inliers, 16);
}

TEST(RobustMapFit, BadOptionsAndInputsAreClearErrors) {
  const std::vector<Eigen::Vector2d> map{{0, 0}, {4, 0}};
  const std::vector<Eigen::Vector2d> points{{0, 0}, {4, 0}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto error = [&](const RobustMapFitOptions& options,
                   std::span<const Eigen::Vector2d> landmarks = {}) {
    const Result<MapFitResult> r =
        RobustFitMap(landmarks.empty() ? std::span<const Eigen::Vector2d>(map) : landmarks, points,
                     {}, {}, options);
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string() : r.status().message();
  };
  EXPECT_NE(error({}).find("search radius"), std::string::npos);
  EXPECT_NE(error({.search_radius_m = nan}).find("search radius"), std::string::npos);
  EXPECT_NE(error({.search_radius_m = 1, .final_radius_m = 0}).find("final_radius_m"),
            std::string::npos);
  EXPECT_NE(error({.search_radius_m = 1, .shrink_factor = 1.0}).find("shrink_factor"),
            std::string::npos);
  EXPECT_NE(error({.search_radius_m = 1, .min_landmarks = 1}).find("min_landmarks"),
            std::string::npos);
  EXPECT_NE(error({.search_radius_m = 1, .ambiguity_ratio = 1.5}).find("ambiguity_ratio"),
            std::string::npos);
  const std::vector<Eigen::Vector2d> broken{{0, 0}, {nan, 1}};
  EXPECT_NE(error({.search_radius_m = 1}, broken).find("landmark 1 is not finite"),
            std::string::npos);
  EXPECT_FALSE(RobustFitMap(map, {}, {}, {}, {.search_radius_m = 1}).ok());
}

}  // namespace
}  // namespace fleetloc::mapmatch
