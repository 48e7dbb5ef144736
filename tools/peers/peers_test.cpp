// The peers on a real floor photo (tracking/test_scene.h): from an odometry prediction a few
// pixels and half a degree off, each must recover the camera pose to about a pixel and 0.2°
// (phase correlation: position only, its heading is the prediction's), keep it over a sequence
// with drifting odometry, and coast on a blank frame and on a frame from another place.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "peers/make_peer.h"
#include "tracking/test_scene.h"

namespace fleetloc::peers {
namespace {

using geometry::Pose2;
using tracking::FrameResult;
using tracking::LockState;

constexpr double kDeg = M_PI / 180.0;

Pose2 CircleBase(double s, const Pose2& mount) {  // camera centre circles the middle of the floor
  const double r = 0.05, cx = 0.128, cy = 0.128;
  const Pose2 camera{cx + r * std::cos(s), cy + r * std::sin(s), s + M_PI / 2};
  return camera * mount.Inverse();
}

struct Errors {
  double position_px = 0.0;
  double heading_rad = 0.0;  // estimate − truth
};

class PeerAccuracy : public ::testing::TestWithParam<std::string> {
 protected:
  tracking::TestScene scene_;
  mosaic::ImageRasterSource source_{scene_.floor, scene_.geo};

  // One frame: the peer starts at the true pose (1-sigma 4 px, 1°, matching the injected error),
  // then odometry predicts the next camera pose off by `camera_error` (in the camera's frame).
  Errors TrackOneFrame(tracking::FrameLocalizer& peer, double s, const Pose2& camera_error) {
    const Pose2& mount = scene_.camera.mount;
    const Pose2 start = CircleBase(s, mount), truth = CircleBase(s + 0.1, mount);
    const Pose2 odom_start{0.3, -0.2, 1.0};  // an arbitrary odom frame
    peer.Reset({start, Eigen::Vector3d(4e-6, 4e-6, std::pow(kDeg, 2)).asDiagonal()}, odom_start);
    const Pose2 predicted_base = truth * mount * camera_error * mount.Inverse();
    const Pose2 odom = odom_start * geometry::Between(start, predicted_base);
    const FrameResult r = peer.Track(scene_.Render(truth, 0.9, 12.0), 0.1, odom);
    EXPECT_EQ(r.state, LockState::kTracking) << peer.name() << " at s = " << s;
    EXPECT_GE(r.inliers, 1);
    const Pose2 estimate = r.base_in_map.pose * mount, camera_truth = truth * mount;
    return {std::hypot(estimate.x - camera_truth.x, estimate.y - camera_truth.y) /
                scene_.camera.resolution_m,
            geometry::WrapAngle(estimate.theta - camera_truth.theta)};
  }
};

TEST_P(PeerAccuracy, RecoversCameraPoseFromAPredictionAFewPixelsAndHalfADegreeOff) {
  ASSERT_FALSE(scene_.floor.empty());
  std::unique_ptr<tracking::FrameLocalizer> peer = MakePeer(GetParam(), scene_.camera, &source_);
  ASSERT_NE(peer, nullptr);
  const bool heading_measured = GetParam() != "phase";
  double max_px = 0, sum_sq_px = 0, max_heading_deg = 0, sum_sq_heading_deg = 0;
  const int trials = 8;
  for (int k = 0; k < trials; ++k) {
    const double px = scene_.camera.resolution_m;
    const double angle = 0.8 * k, heading_error = (k % 2 ? 0.5 : -0.5) * kDeg;
    const Pose2 camera_error{3.0 * px * std::cos(angle), 3.0 * px * std::sin(angle), heading_error};
    const Errors e = TrackOneFrame(*peer, 0.8 * k, camera_error);
    max_px = std::max(max_px, e.position_px);
    sum_sq_px += e.position_px * e.position_px;
    max_heading_deg = std::max(max_heading_deg, std::abs(e.heading_rad) / kDeg);
    sum_sq_heading_deg += std::pow(e.heading_rad / kDeg, 2);
    if (!heading_measured) {  // translation only: the heading must stay the prediction's
      EXPECT_NEAR(e.heading_rad, heading_error, 0.01 * kDeg);
    }
  }
  const double rms_heading_deg = std::sqrt(sum_sq_heading_deg / trials);
  std::printf("%-5s camera position RMS %.3f px, max %.3f px; heading RMS %.3f°, max %.3f°%s\n",
              GetParam().c_str(), std::sqrt(sum_sq_px / trials), max_px, rms_heading_deg,
              max_heading_deg, heading_measured ? "" : " (the prediction's)");
  EXPECT_LT(max_px, 1.0);
  if (heading_measured) {
    // ORB's integer keypoints make its heading the noisiest (RMS ~0.1°, single frames to ~0.4°).
    EXPECT_LT(rms_heading_deg, 0.2);
    EXPECT_LT(max_heading_deg, 0.5);
  }
}

// Tracking-error compensation over a sequence: one Reset, then odometry with 2 % distance and
// 1 % turn scale errors; each prediction starts from the peer's own last estimate.
TEST_P(PeerAccuracy, TracksASequenceWithDriftingOdometry) {
  std::unique_ptr<tracking::FrameLocalizer> peer = MakePeer(GetParam(), scene_.camera, &source_);
  ASSERT_NE(peer, nullptr);
  const Pose2& mount = scene_.camera.mount;
  Pose2 odom{0, 0, 0}, truth_prev = CircleBase(0, mount);
  peer->Reset({truth_prev, Eigen::Vector3d(1e-6, 1e-6, 1e-4).asDiagonal()}, odom);
  double sum_sq_px = 0, sum_sq_deg = 0;
  const int frames = 16;
  for (int k = 1; k <= frames; ++k) {
    const Pose2 truth = CircleBase(0.15 * k, mount);
    const Pose2 step = geometry::Between(truth_prev, truth);
    odom = odom * Pose2{step.x * 1.02, step.y * 1.02, step.theta * 1.01};
    truth_prev = truth;
    const FrameResult r = peer->Track(scene_.Render(truth, 0.85, 10.0), 0.1 * k, odom);
    ASSERT_EQ(r.state, LockState::kTracking) << "frame " << k;
    const Pose2 estimate = r.base_in_map.pose * mount, camera_truth = truth * mount;
    sum_sq_px +=
        (std::pow(estimate.x - camera_truth.x, 2) + std::pow(estimate.y - camera_truth.y, 2)) /
        std::pow(scene_.camera.resolution_m, 2);
    sum_sq_deg += std::pow(geometry::WrapAngle(estimate.theta - camera_truth.theta) / kDeg, 2);
  }
  const double rms_px = std::sqrt(sum_sq_px / frames), rms_deg = std::sqrt(sum_sq_deg / frames);
  std::printf("%-5s sequence: camera position RMS %.3f px, heading RMS %.3f°\n", GetParam().c_str(),
              rms_px, rms_deg);
  if (GetParam() == "phase") {  // the heading drifts with odometry; the position still holds
    EXPECT_LT(rms_px, 1.0);
  } else {
    EXPECT_LT(rms_px, 0.5);
    EXPECT_LT(rms_deg, 0.2);
  }
}

TEST_P(PeerAccuracy, CoastsOnTheExactPredictionForABlankFrame) {
  std::unique_ptr<tracking::FrameLocalizer> peer = MakePeer(GetParam(), scene_.camera, &source_);
  ASSERT_NE(peer, nullptr);
  const Pose2 start = CircleBase(0, scene_.camera.mount);
  peer->Reset({start, Eigen::Vector3d(4e-6, 4e-6, 1e-4).asDiagonal()}, {0, 0, 0});
  const cv::Mat blank(scene_.camera.height_px, scene_.camera.width_px, CV_8UC1, cv::Scalar(90));
  const FrameResult r = peer->Track(blank, 0.1, {0.004, 0.001, 0.01});
  EXPECT_EQ(r.state, LockState::kCoasting);
  EXPECT_EQ(r.inliers, 0);
  const Pose2 predicted = start * Pose2{0.004, 0.001, 0.01};
  EXPECT_NEAR(r.base_in_map.pose.x, predicted.x, 1e-12);
  EXPECT_NEAR(r.base_in_map.pose.y, predicted.y, 1e-12);
  EXPECT_NEAR(r.base_in_map.pose.theta, predicted.theta, 1e-12);
  EXPECT_GT(r.base_in_map.covariance(0, 0), 4e-6);  // uncertainty grew
}

TEST_P(PeerAccuracy, CoastsInsteadOfLockingOntoAFrameFromElsewhere) {
  std::unique_ptr<tracking::FrameLocalizer> peer = MakePeer(GetParam(), scene_.camera, &source_);
  ASSERT_NE(peer, nullptr);
  const Pose2 start = CircleBase(0, scene_.camera.mount);
  peer->Reset({start, Eigen::Vector3d(4e-6, 4e-6, 1e-4).asDiagonal()}, {0, 0, 0});
  // The frame shows another part of the floor: camera 95 mm (190 px) away, turned 143°.
  const Pose2 elsewhere = CircleBase(2.5, scene_.camera.mount);
  const FrameResult r = peer->Track(scene_.Render(elsewhere, 1.0, 0.0), 0.1, {0.002, 0, 0});
  EXPECT_EQ(r.state, LockState::kCoasting);
  EXPECT_EQ(r.inliers, 0);
}

INSTANTIATE_TEST_SUITE_P(AllPeers, PeerAccuracy, ::testing::ValuesIn(PeerNames()),
                         [](const auto& param_info) { return param_info.param; });

TEST(MakePeer, BuildsEveryListedPeerByNameAndRejectsUnknownNames) {
  tracking::TestScene scene;
  mosaic::ImageRasterSource source(scene.floor, scene.geo);
  for (const std::string& name : PeerNames()) {
    const std::unique_ptr<tracking::FrameLocalizer> peer = MakePeer(name, scene.camera, &source);
    ASSERT_NE(peer, nullptr) << name;
    EXPECT_EQ(peer->name(), name);
  }
  EXPECT_EQ(MakePeer("surf", scene.camera, &source), nullptr);
}

}  // namespace
}  // namespace fleetloc::peers
