// Tests for the run simulator: the planned run follows the contract (times, coverage of odometry,
// truth), its odometry drifts as configured, its summary is right and it is reproducible.
#include "sim/run_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "sim/sim_test_util.h"

namespace fleetloc::sim {
namespace {

using testing::kResolutionM;
using testing::SmallCamera;

mosaic::ImageRasterSource GravelFloor() {
  cv::Mat gravel = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(gravel.empty());
  return mosaic::ImageRasterSource(gravel, geometry::Geotransform{1.0, 2.0, kResolutionM});
}

TEST(RunSimulator, PlansAscendingFramesCoveredByOdometry) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.timing.frames = 40;
  auto sim = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  const auto& truth = (*sim)->truth();
  const auto& odom = (*sim)->odometry();
  ASSERT_EQ((*sim)->frame_count(), 40);
  for (size_t i = 1; i < truth.size(); ++i) {
    EXPECT_GT(truth[i].t, truth[i - 1].t);
    EXPECT_NEAR(truth[i].t - truth[i - 1].t, 0.2, 2 * options.timing.frame_jitter_s + 1e-12);
  }
  for (size_t k = 1; k < odom.size(); ++k) EXPECT_GT(odom[k].t, odom[k - 1].t);
  EXPECT_LT(odom.front().t, truth.front().t);
  EXPECT_GT(odom.back().t, truth.back().t);
  EXPECT_NEAR(odom.size() / (odom.back().t - odom.front().t), 100.0, 3.0);
}

TEST(RunSimulator, TruthPutsTheCameraOnTheRouteThroughTheMount) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.timing.frames = 10;
  auto sim = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(sim.ok());
  for (const auto& base : (*sim)->truth()) {
    const geometry::Pose2 camera = base.pose * SmallCamera().mount;
    const geometry::Pose2 on_route =
        (*sim)->route().CameraPoseAt(base.t - options.timing.start_time_s);
    EXPECT_NEAR(camera.x, on_route.x, 1e-12);
    EXPECT_NEAR(camera.y, on_route.y, 1e-12);
    EXPECT_NEAR(geometry::WrapAngle(camera.theta - on_route.theta), 0.0, 1e-12);
    // The mount puts base_link 0.40 m behind the camera.
    EXPECT_NEAR(std::hypot(camera.x - base.pose.x, camera.y - base.pose.y), 0.40, 1e-12);
  }
}

TEST(RunSimulator, OdometryLengthIsTruthLengthTimesOnePlusScaleError) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options = CleanSimOptions(SimOptions{});
  options.timing.frames = 50;
  options.odometry.distance_scale_error = 0.02;
  auto sim = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(sim.ok());
  double odom_length = 0.0, truth_length = 0.0;
  const auto& odom = (*sim)->odometry();
  for (size_t k = 1; k < odom.size(); ++k) {
    odom_length +=
        std::hypot(odom[k].pose.x - odom[k - 1].pose.x, odom[k].pose.y - odom[k - 1].pose.y);
    const geometry::Pose2 a = (*sim)->TruthAt(odom[k - 1].t), b = (*sim)->TruthAt(odom[k].t);
    truth_length += std::hypot(b.x - a.x, b.y - a.y);
  }
  EXPECT_NEAR(odom_length / truth_length, 1.02, 1e-9);
  EXPECT_GT((*sim)->summary().odometry_drift_m, 0.0);
}

TEST(RunSimulator, SummaryReportsSpeedOverlapAndCoverage) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.timing.frames = 30;
  options.timing.frame_jitter_s = 0.0;
  auto fast = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(fast.ok());
  const SimSummary& s = (*fast)->summary();
  EXPECT_EQ(s.frames, 30);
  EXPECT_NEAR(s.duration_s, 29 * 0.2, 1e-9);
  EXPECT_NEAR(s.speed_px_s, 3000.0, 1.0);
  EXPECT_NEAR(s.distance_m, 29 * 0.2 * 3000.0 * kResolutionM, 1e-9);
  // 600 px between 128-px frames: no successive pair overlaps.
  EXPECT_EQ(s.overlapping_pairs_fraction, 0.0);
  EXPECT_GE(s.min_frame_on_floor, 0.6 - 1e-3);
  EXPECT_GT(s.floor_fraction_seen, 0.3);
  EXPECT_LE(s.floor_fraction_seen, 1.0);

  options.route.speed_px_s = 100.0;  // 20 px between frames: every pair overlaps, by ~80 %
  auto slow = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(slow.ok());
  EXPECT_EQ((*slow)->summary().overlapping_pairs_fraction, 1.0);
  EXPECT_NEAR((*slow)->summary().mean_pair_overlap, 0.8, 0.1);
}

TEST(RunSimulator, InitialPoseIsTruthPerturbedWithinSigma) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.timing.frames = 2;
  options.initial_pose.perturb = false;
  auto exact = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(exact.ok());
  EXPECT_EQ((*exact)->initial_pose().x, (*exact)->truth().front().pose.x);
  options.initial_pose.perturb = true;
  auto perturbed = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(perturbed.ok());
  const geometry::Pose2 error =
      geometry::Between((*perturbed)->truth().front().pose, (*perturbed)->initial_pose());
  EXPECT_GT(std::hypot(error.x, error.y), 0.0);
  EXPECT_LT(std::hypot(error.x, error.y), 5 * 0.002 * std::sqrt(2.0));
  EXPECT_LT(std::abs(error.theta), 5 * 0.5 * M_PI / 180.0);
}

TEST(RunSimulator, SameSeedSameRunAndFrames) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.timing.frames = 5;
  options.seed = 77;
  auto a = RunSimulator::Create(&floor, SmallCamera(), options);
  auto b = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ((*a)->odometry().back().pose.x, (*b)->odometry().back().pose.x);
  EXPECT_EQ((*a)->truth().back().t, (*b)->truth().back().t);
  EXPECT_EQ((*a)->initial_pose().theta, (*b)->initial_pose().theta);
  EXPECT_EQ(cv::norm((*a)->RenderFrame(3).image, (*b)->RenderFrame(3).image, cv::NORM_INF), 0.0);
}

TEST(RunSimulator, RejectsInvalidOptionsNamingTheField) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.timing.odometry_rate_hz = 2.0;  // below the frame rate
  auto sim = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_FALSE(sim.ok());
  EXPECT_EQ(sim.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(sim.status().message().find("odometry_rate_hz"), std::string::npos);
  geometry::CameraModel camera = SmallCamera();
  camera.resolution_m = 0.0;
  EXPECT_FALSE(RunSimulator::Create(&floor, camera, SimOptions{}).ok());
}

TEST(RunSimulator, KidnapMovesTheFramesButNotTheOdometry) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options = CleanSimOptions(SimOptions{});
  options.timing.frames = 40;
  options.kidnap.at_s = 4.0;  // between frames 19 (3.85 s) and 20 (4.05 s)
  options.kidnap.jump_fraction = 0.5;
  auto sim = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  const auto& truth = (*sim)->truth();
  const Route& route = (*sim)->route();
  const geometry::Pose2 mount_inverse = SmallCamera().mount.Inverse();
  for (const geometry::StampedPose& base : truth) {
    const double elapsed = base.t - options.timing.start_time_s;
    const double jump = elapsed >= 4.0 ? 0.5 * route.length_m() : 0.0;
    const geometry::Pose2 expected =
        route.CameraPoseAtArcLength(route.ArcLengthAt(elapsed) + jump) * mount_inverse;
    EXPECT_NEAR(base.pose.x, expected.x, 1e-12);
    EXPECT_NEAR(base.pose.y, expected.y, 1e-12);
  }
  const double truth_step =
      std::hypot(truth[20].pose.x - truth[19].pose.x, truth[20].pose.y - truth[19].pose.y);
  EXPECT_GT(truth_step, 0.05);  // the vehicle was carried off (a frame step is ~0.3 m · 0.2 s)
  // Exact odometry without jitter (clean options) has a sample at every frame time: its increment
  // over the jump is the motion without it, and after it every increment is the truth's.
  auto odom_at = [&](double t) {
    for (const auto& sample : (*sim)->odometry()) {
      if (std::abs(sample.t - t) < 1e-9) return sample.pose;
    }
    ADD_FAILURE() << "no odometry sample at t=" << t;
    return geometry::Pose2{};
  };
  auto odom_between = [&](int a, int b) {
    return geometry::Between(odom_at(truth[a].t), odom_at(truth[b].t));
  };
  // Across the jump: the motion up to the pick-up, then the motion since the set-down.
  auto base_on_route = [&](double t, double jump_m) {
    return route.CameraPoseAtArcLength(route.ArcLengthAt(t) + jump_m) * mount_inverse;
  };
  const double jump_m = 0.5 * route.length_m();
  const geometry::Pose2 expected_across =
      geometry::Between(truth[19].pose, base_on_route(4.0, 0.0)) *
      geometry::Between(base_on_route(4.0, jump_m), truth[20].pose);
  const geometry::Pose2 across = odom_between(19, 20);
  EXPECT_NEAR(across.x, expected_across.x, 1e-9);
  EXPECT_NEAR(across.y, expected_across.y, 1e-9);
  EXPECT_NEAR(across.theta, expected_across.theta, 1e-9);
  for (int i = 21; i < 40; ++i) {
    const geometry::Pose2 odom = odom_between(i - 1, i);
    const geometry::Pose2 moved = geometry::Between(truth[i - 1].pose, truth[i].pose);
    EXPECT_NEAR(odom.x, moved.x, 1e-3);
    EXPECT_NEAR(odom.y, moved.y, 1e-3);
    EXPECT_NEAR(odom.theta, moved.theta, 1e-3);
  }
}

TEST(RunSimulator, RejectsAKidnapJumpOutsideTheRoute) {
  mosaic::ImageRasterSource floor = GravelFloor();
  SimOptions options;
  options.kidnap.at_s = 1.0;
  options.kidnap.jump_fraction = 1.5;
  auto sim = RunSimulator::Create(&floor, SmallCamera(), options);
  ASSERT_FALSE(sim.ok());
  EXPECT_NE(sim.status().message().find("kidnap_jump_fraction"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::sim
