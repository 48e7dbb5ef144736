// Global position update: a simulated vehicle with biased odometry drives down a corridor of
// corners, detecting some of them (and clutter) each frame; the update brings the drifted estimate
// back to the truth. Also the window's bookkeeping and the bad inputs.
#include "mapmatch/global_position_update.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "mapmatch/map_fit_problem.h"

namespace fleetloc::mapmatch {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kFrameS = 0.1;

// Corners on both walls of a 3 m wide corridor, every 2.5 m.
std::vector<Eigen::Vector2d> CorridorCorners() {
  std::vector<Eigen::Vector2d> corners;
  for (int k = -2; k <= 40; ++k) {
    corners.emplace_back(2.5 * k, 1.5);
    corners.emplace_back(2.5 * k + 1.2, -1.5);
  }
  return corners;
}

// A vehicle at 1 m/s weaving gently down the corridor; its odometry reads 3 % long and turns
// 0.3 °/s too far left. It sees corners 0.5–5 m ahead (60 % of them per frame, σ = 2 cm) and three
// clutter points per frame.
class DriftingVehicle {
 public:
  DriftingVehicle(unsigned seed, const geometry::Pose2& estimate_error)
      : rng_(seed), estimate_(estimate_error) {}

  // Advances one frame and adds its detections to `window` with the current estimate.
  void Step(const std::vector<Eigen::Vector2d>& corners, DetectionWindow* window) {
    t_s_ += kFrameS;
    const double turn_rad = 0.04 * std::cos(0.4 * t_s_) * kFrameS;  // heading ±0.1 rad
    truth_ = truth_ * geometry::Pose2{kFrameS, 0.0, turn_rad};
    estimate_ = estimate_ * geometry::Pose2{1.03 * kFrameS, 0.0, turn_rad + 0.3 * kDeg * kFrameS};
    drift_only_ =
        drift_only_ * geometry::Pose2{1.03 * kFrameS, 0.0, turn_rad + 0.3 * kDeg * kFrameS};
    ASSERT_TRUE(window->Add(t_s_, estimate_, Detect(corners)).ok());
  }
  void Correct(const geometry::Pose2& correction) { estimate_ = correction * estimate_; }

  double t_s() const { return t_s_; }
  const geometry::Pose2& truth() const { return truth_; }
  const geometry::Pose2& estimate() const { return estimate_; }
  const geometry::Pose2& drift_only() const { return drift_only_; }

 private:
  std::vector<Eigen::Vector2d> Detect(const std::vector<Eigen::Vector2d>& corners) {
    std::normal_distribution<double> noise(0.0, 0.02);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Eigen::Vector2d> seen;
    const geometry::Pose2 to_vehicle = truth_.Inverse();
    for (const Eigen::Vector2d& corner : corners) {
      const Eigen::Vector2d v = to_vehicle * corner;
      if (v.x() < 0.5 || v.norm() > 5.0 || unit(rng_) < 0.4) continue;
      seen.emplace_back(v.x() + noise(rng_), v.y() + noise(rng_));
    }
    for (int k = 0; k < 3; ++k) seen.emplace_back(0.5 + 3.5 * unit(rng_), -2 + 4 * unit(rng_));
    return seen;
  }

  std::mt19937 rng_;
  double t_s_ = 0.0;
  geometry::Pose2 truth_;
  geometry::Pose2 estimate_;    // odometry, corrected by the updates
  geometry::Pose2 drift_only_;  // odometry alone, from the true start
};

double PositionError(const geometry::Pose2& a, const geometry::Pose2& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

TEST(GlobalPositionUpdate, OneUpdateRemovesTheAccumulatedError) {
  const std::vector<Eigen::Vector2d> corners = CorridorCorners();
  const GlobalPositionUpdateOptions options{.weight_half_life_s = 2.0};
  for (unsigned seed = 1; seed <= 20; ++seed) {
    // The estimate starts 15 cm and 1° off and drifts for 6 s; the window holds the last 2 s.
    DriftingVehicle vehicle(seed, {0.15, -0.05, 1.0 * kDeg});
    DetectionWindow window(2.0);
    for (int frame = 0; frame < 60; ++frame) vehicle.Step(corners, &window);
    const double drifted = PositionError(vehicle.estimate(), vehicle.truth());
    ASSERT_GT(drifted, 0.2) << "seed " << seed;
    const PositionUpdate update =
        UpdateGlobalPosition(window, vehicle.t_s(), corners,
                             {vehicle.estimate(), Eigen::Matrix3d::Identity()}, options)
            .value();
    ASSERT_TRUE(update.applied) << "seed " << seed << ": " << update.fit.reason;
    const double corrected = PositionError(update.pose.pose, vehicle.truth());
    // Measured over these seeds: 35 cm → 1.9–3.2 cm and at most 0.45°; what remains is the
    // odometry's own drift within the 2 s window (3 % of 2 m).
    EXPECT_LT(corrected, 0.15 * drifted) << "seed " << seed;
    EXPECT_LT(corrected, 0.05) << "seed " << seed;
    EXPECT_LT(std::abs(geometry::WrapAngle(update.pose.pose.theta - vehicle.truth().theta)),
              0.75 * kDeg)
        << "seed " << seed;
    // The covariance is the fit's, carried to the pose: centimetres, not the prior's metre.
    EXPECT_LT(update.pose.covariance(0, 0), 1e-3);
    EXPECT_GT(update.pose.covariance(0, 0), 0.0);
  }
}

TEST(GlobalPositionUpdate, UpdatesEverySecondKeepTheVehicleOnTheMap) {
  const std::vector<Eigen::Vector2d> corners = CorridorCorners();
  DriftingVehicle vehicle(5, {});
  DetectionWindow window(2.0);
  double worst_corrected = 0.0;
  int applied = 0;
  for (int frame = 1; frame <= 900; ++frame) {  // 90 m
    vehicle.Step(corners, &window);
    if (frame % 10 != 0 || frame < 20) continue;
    const PositionUpdate update =
        UpdateGlobalPosition(window, vehicle.t_s(), corners,
                             {vehicle.estimate(), Eigen::Matrix3d::Zero()},
                             {.weight_half_life_s = 1.0})
            .value();
    if (!update.applied) continue;
    ++applied;
    vehicle.Correct(update.fit.correction);
    window.ApplyCorrection(update.fit.correction);
    worst_corrected = std::max(worst_corrected, PositionError(vehicle.estimate(), vehicle.truth()));
  }
  EXPECT_GE(applied, 85);  // of 89 updates
  const double drift_only = PositionError(vehicle.drift_only(), vehicle.truth());
  EXPECT_GT(drift_only, 5.0) << "odometry alone is metres off after 90 m";
  EXPECT_LT(worst_corrected, 0.05);
}

TEST(GlobalPositionUpdate, TheWindowDropsOldPointsAndWeighsByAge) {
  DetectionWindow window(1.0);
  const std::vector<Eigen::Vector2d> one{{1.0, 0.0}};
  ASSERT_TRUE(window.Add(0.0, {}, one).ok());
  ASSERT_TRUE(window.Add(0.5, {0, 0, M_PI / 2}, one).ok());
  EXPECT_EQ(window.size(), 2u);
  EXPECT_NEAR(window.MapPoints()[1].y(), 1.0, 1e-12);  // placed with the pose at its time
  const std::vector<double> weights = window.Weights(1.0, 0.5);
  EXPECT_DOUBLE_EQ(weights[0], 0.25);
  EXPECT_DOUBLE_EQ(weights[1], 0.5);
  ASSERT_TRUE(window.Add(1.2, {}, one).ok());
  EXPECT_EQ(window.size(), 2u) << "the point of t = 0 is older than 1 s";
  window.ApplyCorrection({1.0, 2.0, 0.0});
  EXPECT_EQ(window.MapPoints()[1], Eigen::Vector2d(2.0, 2.0));
  window.DropOlderThanWindow(10.0);
  EXPECT_TRUE(window.empty());
}

TEST(GlobalPositionUpdate, BadInputIsAClearError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Eigen::Vector2d> corners = CorridorCorners();
  DetectionWindow window(1.0);
  const std::vector<Eigen::Vector2d> with_nan{{1.0, 0.0}, {nan, 0.0}};
  EXPECT_NE(window.Add(0.0, {}, with_nan).message().find("point 1"), std::string::npos);
  EXPECT_NE(window.Add(0.0, {nan, 0, 0}, {}).message().find("pose"), std::string::npos);
  EXPECT_TRUE(window.empty()) << "nothing added from a bad frame";
  const Result<PositionUpdate> empty = UpdateGlobalPosition(window, 0.0, corners, {}, {});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("window is empty"), std::string::npos);
  const std::vector<Eigen::Vector2d> one{{1.0, 0.0}};
  ASSERT_TRUE(window.Add(1.0, {}, one).ok());
  EXPECT_FALSE(window.Add(0.5, {}, one).ok()) << "time going backwards";
  EXPECT_FALSE(UpdateGlobalPosition(window, 0.5, corners, {}, {}).ok());
  EXPECT_FALSE(
      UpdateGlobalPosition(window, 1.0, corners, {{nan, 0, 0}, Eigen::Matrix3d::Zero()}, {}).ok());
  EXPECT_FALSE(UpdateGlobalPosition(window, 1.0, corners, {}, {.weight_half_life_s = -1}).ok());
  // Far from every landmark: not an error, just no update.
  DetectionWindow far(1.0);
  ASSERT_TRUE(far.Add(0.0, {500, 500, 0}, one).ok());
  const PositionUpdate none = UpdateGlobalPosition(far, 0.0, corners, {}, {}).value();
  EXPECT_FALSE(none.applied);
  EXPECT_NE(none.fit.reason.find("no landmark"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::mapmatch
