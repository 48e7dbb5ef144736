// Tests for the Kalman pose update: exact recovery, outlier rejection, prior dominance.
#include "tracking/pose_update.h"

#include <gtest/gtest.h>

#include <random>

namespace fleetloc::tracking {
namespace {

using geometry::Pose2;

std::vector<Correspondence> Observe(const Pose2& truth, int n, double noise_m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> spread(-0.15, 0.15);
  std::normal_distribution<double> noise(0.0, noise_m);
  std::vector<Correspondence> out;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d g(spread(rng), spread(rng));
    out.push_back({g, truth * g + Eigen::Vector2d(noise(rng), noise(rng)), 1e-4});
  }
  return out;
}

TEST(KalmanPoseUpdate, RecoversPoseFromNoisyCorrespondences) {
  const Pose2 truth{2.0, -1.0, 0.3};
  const geometry::PoseWithCovariance prior{{2.004, -1.003, 0.31},
                                           Eigen::Vector3d(1e-5, 1e-5, 1e-4).asDiagonal()};
  const PoseUpdate u = KalmanPoseUpdate(prior, Observe(truth, 20, 5e-5, 1), {});
  EXPECT_EQ(u.inliers, 20);
  EXPECT_NEAR(u.posterior.pose.x, truth.x, 3e-5);
  EXPECT_NEAR(u.posterior.pose.y, truth.y, 3e-5);
  EXPECT_NEAR(u.posterior.pose.theta, truth.theta, 3e-4);
  EXPECT_LT(u.posterior.covariance(0, 0), prior.covariance(0, 0) / 100);
  EXPECT_NEAR(u.rms_residual_m, 5e-5 * std::sqrt(2.0), 3e-5);
}

TEST(KalmanPoseUpdate, RemovesGrossOutliersOneByOne) {
  const Pose2 truth{0.5, 0.5, -1.0};
  std::vector<Correspondence> m = Observe(truth, 16, 3e-5, 2);
  m[3].observed += Eigen::Vector2d(0.004, 0.0);  // 8 px at 0.5 mm/px
  m[9].observed += Eigen::Vector2d(-0.002, 0.003);
  const geometry::PoseWithCovariance prior{{0.502, 0.499, -1.01},
                                           Eigen::Vector3d(1e-5, 1e-5, 1e-3).asDiagonal()};
  const PoseUpdate u = KalmanPoseUpdate(prior, m, {});
  EXPECT_FALSE(u.inlier[3]);
  EXPECT_FALSE(u.inlier[9]);
  EXPECT_EQ(u.inliers, 14);
  EXPECT_NEAR(u.posterior.pose.x, truth.x, 3e-5);
  EXPECT_NEAR(u.posterior.pose.theta, truth.theta, 3e-4);
}

TEST(KalmanPoseUpdate, FewerThanTwoMatchesLeavesThePrior) {
  const geometry::PoseWithCovariance prior{{1, 2, 3}, Eigen::Matrix3d::Identity() * 1e-4};
  const PoseUpdate u = KalmanPoseUpdate(prior, Observe({1, 2, 3}, 1, 0, 3), {});
  EXPECT_EQ(u.inliers, 0);
  EXPECT_EQ(u.posterior.pose.x, 1);
}

}  // namespace
}  // namespace fleetloc::tracking
