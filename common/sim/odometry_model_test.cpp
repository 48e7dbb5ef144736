// Tests for the odometry error model: its drift matches the configured scale errors, heading bias
// and noise densities.
#include "sim/odometry_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::sim {
namespace {

constexpr double kRateHz = 100.0;

// base_link driving straight at 1 m/s for `seconds`, heading 0.3 rad, from (2, 3).
std::vector<geometry::StampedPose> StraightLine(double seconds) {
  std::vector<geometry::StampedPose> truth;
  for (int k = 0; k <= seconds * kRateHz; ++k) {
    const double t = k / kRateHz;
    truth.push_back({t, {2.0 + t * std::cos(0.3), 3.0 + t * std::sin(0.3), 0.3}});
  }
  return truth;
}

// base_link on a circle of radius 1 m at 0.5 m/s (0.5 rad/s) for `seconds`.
std::vector<geometry::StampedPose> Circle(double seconds) {
  std::vector<geometry::StampedPose> truth;
  for (int k = 0; k <= seconds * kRateHz; ++k) {
    const double t = k / kRateHz, a = 0.5 * t;
    truth.push_back({t, {std::sin(a), 1.0 - std::cos(a), geometry::WrapAngle(a)}});
  }
  return truth;
}

OdometryOptions NoErrors() {
  OdometryOptions options;
  options.distance_scale_error = 0.0;
  options.heading_scale_error = 0.0;
  options.heading_drift_rad_s = 0.0;
  options.distance_noise_m_per_sqrt_m = 0.0;
  options.heading_noise_rad_per_sqrt_s = 0.0;
  return options;
}

double PathLength(const std::vector<geometry::StampedPose>& poses) {
  double length = 0.0;
  for (size_t k = 1; k < poses.size(); ++k) {
    length +=
        std::hypot(poses[k].pose.x - poses[k - 1].pose.x, poses[k].pose.y - poses[k - 1].pose.y);
  }
  return length;
}

// Total turn, unwrapped.
double Turn(const std::vector<geometry::StampedPose>& poses) {
  double turn = 0.0;
  for (size_t k = 1; k < poses.size(); ++k) {
    turn += geometry::WrapAngle(poses[k].pose.theta - poses[k - 1].pose.theta);
  }
  return turn;
}

TEST(OdometryModel, WithoutErrorsReproducesTruth) {
  const auto truth = Circle(10.0);
  const auto odom = SimulateOdometry(truth, NoErrors(), 1);
  ASSERT_EQ(odom.size(), truth.size());
  for (size_t k = 0; k < truth.size(); ++k) {
    EXPECT_DOUBLE_EQ(odom[k].t, truth[k].t);
    EXPECT_NEAR(odom[k].pose.x, truth[k].pose.x, 1e-9);
    EXPECT_NEAR(odom[k].pose.y, truth[k].pose.y, 1e-9);
  }
}

TEST(OdometryModel, DrivenDistanceGrowsByTheScaleError) {
  OdometryOptions options = NoErrors();
  options.distance_scale_error = 0.01;
  const auto truth = StraightLine(10.0);  // D = 10 m
  const auto odom = SimulateOdometry(truth, options, 1);
  EXPECT_NEAR(PathLength(odom), 10.0 * 1.01, 1e-9);
  // Heading unaffected on a straight line.
  EXPECT_NEAR(odom.back().pose.theta, 0.3, 1e-12);
}

TEST(OdometryModel, TurnsGrowByTheHeadingScaleErrorPlusDrift) {
  OdometryOptions options = NoErrors();
  options.heading_scale_error = 0.01;
  options.heading_drift_rad_s = 0.2 * M_PI / 180.0;
  const auto truth = Circle(20.0);  // 10 rad of turning in 20 s
  const auto odom = SimulateOdometry(truth, options, 1);
  EXPECT_NEAR(Turn(truth), 10.0, 1e-9);
  EXPECT_NEAR(Turn(odom), 10.0 * 1.01 + 20.0 * 0.2 * M_PI / 180.0, 1e-9);
  // Distance is exact when only heading errs.
  EXPECT_NEAR(PathLength(odom), PathLength(truth), 1e-9);
}

TEST(OdometryModel, WhiteNoiseGrowsWithTheSquareRootOfDistanceAndTime) {
  OdometryOptions options = NoErrors();
  options.distance_noise_m_per_sqrt_m = 0.002;
  options.heading_noise_rad_per_sqrt_s = 0.001;
  const auto truth = StraightLine(4.0);  // 4 m in 4 s
  const int runs = 400;
  double sum2_length = 0.0, sum2_turn = 0.0;
  for (int seed = 0; seed < runs; ++seed) {
    const auto odom = SimulateOdometry(truth, options, seed);
    sum2_length += std::pow(PathLength(odom) - 4.0, 2);
    sum2_turn += std::pow(Turn(odom), 2);
  }
  // σ = 0.002 · √4 m and 0.001 · √4 rad; 400 runs estimate σ within about ±7 %.
  EXPECT_NEAR(std::sqrt(sum2_length / runs), 0.004, 0.004 * 0.15);
  EXPECT_NEAR(std::sqrt(sum2_turn / runs), 0.002, 0.002 * 0.15);
}

TEST(OdometryModel, StartsAtTruthOrAtTheGivenOdomPose) {
  const auto truth = StraightLine(1.0);
  EXPECT_NEAR(SimulateOdometry(truth, OdometryOptions{}, 3).front().pose.x, 2.0, 1e-12);
  OdometryOptions options = NoErrors();
  options.start_pose = geometry::Pose2{0.0, 0.0, 0.0};
  const auto odom = SimulateOdometry(truth, options, 3);
  // Same motion, expressed from the odom origin: 1 m along heading 0.
  EXPECT_NEAR(odom.back().pose.x, 1.0, 1e-9);
  EXPECT_NEAR(odom.back().pose.y, 0.0, 1e-9);
}

TEST(OdometryModel, SameSeedSameDrift) {
  const auto truth = Circle(5.0);
  const auto a = SimulateOdometry(truth, OdometryOptions{}, 9);
  const auto b = SimulateOdometry(truth, OdometryOptions{}, 9);
  const auto c = SimulateOdometry(truth, OdometryOptions{}, 10);
  EXPECT_EQ(a.back().pose.x, b.back().pose.x);
  EXPECT_NE(a.back().pose.x, c.back().pose.x);
}

}  // namespace
}  // namespace fleetloc::sim
