// The agent's position update on rendered corridor images (sim/forward_renderer.h, the images of
// `fleetctl sim-forward --seed 4`): an estimate 15 cm and 1.5° off is brought back to the truth by
// the fits and kept there; fits on too few landmarks or that jump too far are rejected; a tracked
// pose is left alone with the disagreement reported; bad images, an empty window and broken
// landmark maps are counted or refused with a message, never a crash.
#include "tracker_agent/agent_position_update.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sim/forward_renderer.h"
#include "sim/forward_run.h"
#include "sim/random.h"

namespace fleetloc::tracker_agent {
namespace {

constexpr double kDeg = M_PI / 180.0;

double PositionError(const geometry::Pose2& a, const geometry::Pose2& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

// fleetctl sim-forward's camera: 640×480, 1 m above the floor, pitched 0.25 rad down.
mapmatch::ForwardCameraParams TestCamera() {
  mapmatch::ForwardCameraParams camera;
  camera.K = {520, 0, 320, 0, 520, 240, 0, 0, 1};
  camera.dist = {-0.08, 0.01, 0, 0, 0};
  camera.mount = {.x_m = 0.45, .height_m = 1.0, .pitch_rad = 0.25};
  return camera;
}

std::unique_ptr<AgentPositionUpdate> Create() {
  return AgentPositionUpdate::Create(TestCamera(), sim::BuildCorridorScene({}).landmarks, {})
      .value();
}

// A 6 s drive at 2 images per second down the default corridor, rendered once for the tests.
class RenderedDrive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::ForwardRunOptions options;
    options.frames = 13;
    options.seed = 4;
    const sim::CorridorScene scene = sim::BuildCorridorScene(options.scene);
    const sim::ForwardRenderer renderer(mapmatch::ForwardCamera::Create(TestCamera()).value(), {});
    for (const geometry::StampedPose& truth : sim::PlanForwardRun(options).frame_truth) {
      truth_.push_back(truth);
      images_.push_back(
          renderer.Render(scene, truth.pose, sim::MixSeed(options.seed, truth_.size() - 1)));
    }
  }

  static inline std::vector<geometry::StampedPose> truth_;
  static inline std::vector<cv::Mat> images_;
};

TEST_F(RenderedDrive, FitsBringADriftedEstimateBackToTheTruth) {
  std::unique_ptr<AgentPositionUpdate> update = Create();
  // The estimate is the truth moved by a fixed error (as if the start was off), then by what the
  // applied corrections changed.
  geometry::Pose2 correction;
  const geometry::Pose2 error{0.15, -0.05, 1.5 * kDeg};
  double worst_after_first = 0.0;
  int used = 0;
  for (std::size_t i = 0; i < images_.size(); ++i) {
    const double t = truth_[i].t;
    const geometry::Pose2 estimate = correction * error * truth_[i].pose;
    ASSERT_TRUE(update->AddImage(t, images_[i], estimate).ok());
    const auto corrected = update->Update(t, {estimate, Eigen::Matrix3d::Identity()}, true);
    if (corrected) {
      ++used;
      correction = corrected->pose * estimate.Inverse() * correction;
      EXPECT_LT(corrected->covariance(0, 0), 1e-3) << "the fit's covariance, not the prior's";
    }
    const double now = PositionError(correction * error * truth_[i].pose, truth_[i].pose);
    if (used > 0) worst_after_first = std::max(worst_after_first, now);
  }
  const PositionUpdateStats& stats = update->stats();
  EXPECT_EQ(stats.images, 13);
  EXPECT_GT(stats.points, 13 * 4) << "a few corners per image";
  EXPECT_EQ(stats.attempted, 6) << "one fit per second of images after the first";
  EXPECT_GE(stats.applied, 5) << stats.last_reason;
  EXPECT_EQ(used, stats.applied);
  EXPECT_GT(stats.max_correction_m, 0.1) << "the first fit removes most of the 16 cm";
  EXPECT_LT(worst_after_first, 0.02);  // measured 10 mm
  EXPECT_EQ(stats.not_needed, 0);
}

TEST_F(RenderedDrive, FitsOnTooFewLandmarksOrThatJumpTooFarAreRejected) {
  auto rejects = [&](const PositionUpdateOptions& options, const std::string& reason) {
    auto update =
        AgentPositionUpdate::Create(TestCamera(), sim::BuildCorridorScene({}).landmarks, options)
            .value();
    const geometry::Pose2 error{0.1, 0.0, 0.0};
    for (std::size_t i = 0; i < 5; ++i) {
      const geometry::Pose2 estimate = error * truth_[i].pose;
      ASSERT_TRUE(update->AddImage(truth_[i].t, images_[i], estimate).ok());
      EXPECT_FALSE(update->Update(truth_[i].t, {estimate, Eigen::Matrix3d::Zero()}, true));
    }
    EXPECT_EQ(update->stats().rejected, 2);
    EXPECT_EQ(update->stats().applied, 0);
    EXPECT_NE(update->stats().last_reason.find(reason), std::string::npos)
        << update->stats().last_reason;
  };
  PositionUpdateOptions many_landmarks;
  many_landmarks.fit.fit.min_landmarks = 50;  // the fit's validation refuses it
  rejects(many_landmarks, "fewer than 50");
  rejects({.max_correction_m = 0.05}, "would move the pose");
}

TEST_F(RenderedDrive, ATrackedPoseIsLeftAloneAndTheDisagreementReported) {
  std::unique_ptr<AgentPositionUpdate> update = Create();
  const geometry::Pose2 error{0.1, 0.0, 0.0};
  for (std::size_t i = 0; i < 5; ++i) {
    const geometry::Pose2 estimate = error * truth_[i].pose;
    ASSERT_TRUE(update->AddImage(truth_[i].t, images_[i], estimate).ok());
    (void)update->Update(truth_[i].t, {estimate, Eigen::Matrix3d::Zero()}, false);
  }
  const PositionUpdateStats& stats = update->stats();
  EXPECT_EQ(stats.applied, 0);
  EXPECT_EQ(stats.not_needed, 2);
  EXPECT_NEAR(stats.last_disagreement_m, 0.1, 0.03);
  EXPECT_EQ(stats.last_correction_m, 0.0);
}

TEST(AgentPositionUpdate, BadImagesAreCountedAndAnEmptyWindowIsRejected) {
  std::unique_ptr<AgentPositionUpdate> update = Create();
  EXPECT_FALSE(update->Update(0.0, {}, true)) << "nothing is due before the first image";
  const Status small = update->AddImage(0.0, cv::Mat(48, 64, CV_8UC1, cv::Scalar(0)), {});
  EXPECT_NE(small.message().find("forward image at t=0"), std::string::npos) << small.message();
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  ASSERT_TRUE(update->AddImage(0.5, blank, {}).ok());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(update->AddImage(1.0, blank, {nan, 0, 0}).ok()) << "a non-finite estimate";
  EXPECT_FALSE(update->AddImage(0.2, blank, {}).ok()) << "time going backwards";
  ASSERT_TRUE(update->AddImage(1.5, blank, {}).ok());
  EXPECT_FALSE(update->Update(1.5, {}, true));
  const PositionUpdateStats& stats = update->stats();
  EXPECT_EQ(stats.images, 5);
  EXPECT_EQ(stats.images_rejected, 3);
  EXPECT_EQ(stats.attempted, 1);
  EXPECT_EQ(stats.rejected, 1);
  EXPECT_TRUE(stats.last_rejected);
  EXPECT_NE(stats.last_reason.find("no floor points"), std::string::npos) << stats.last_reason;
}

TEST(AgentPositionUpdate, ABrokenLandmarkMapOrCameraIsRefused) {
  const mapmatch::ForwardCameraParams good = TestCamera();
  const std::vector<Eigen::Vector2d> landmarks = sim::BuildCorridorScene({}).landmarks;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto refused = [&](std::vector<Eigen::Vector2d> map, const std::string& what,
                     mapmatch::ForwardCameraParams camera = TestCamera()) {
    auto update = AgentPositionUpdate::Create(camera, std::move(map), {});
    ASSERT_FALSE(update.ok()) << what;
    EXPECT_NE(update.status().message().find(what), std::string::npos) << update.status().message();
  };
  refused({}, "empty");
  refused({{0, 0}, {1, nan}}, "landmark 1 is not finite");
  refused({{0, 0}, {2, 1}, {0, 0}}, "same position");
  mapmatch::ForwardCameraParams camera = good;
  camera.mount.height_m = -1;
  refused(landmarks, "mount.height", camera);
  EXPECT_FALSE(AgentPositionUpdate::Create(good, landmarks, {.period_s = 0}).ok());
  EXPECT_FALSE(AgentPositionUpdate::Create(good, landmarks, {.max_correction_m = 0}).ok());
}

}  // namespace
}  // namespace fleetloc::tracker_agent
