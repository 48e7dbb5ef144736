// Tests for frame-to-frame registration on two views of a real photo (tests/data/gravel.png,
// rendered at known poses with blur, gain, bias and noise by tracking/test_scene.h): the known
// offset and rotation are recovered to a few hundredths of a pixel, independently of the
// prediction, and frames that do not overlap are refused.
#include "mapping/frame_registration.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "geometry/footprint.h"
#include "tracking/test_scene.h"

namespace fleetloc::mapping {
namespace {

using geometry::Pose2;

// A 320×240 camera (mount ignored by registration) over the 512² photo at 0.5 mm per pixel.
tracking::TestScene Scene() {
  tracking::TestScene scene;
  scene.camera.width_px = 320;
  scene.camera.height_px = 240;
  scene.camera.cx_px = 160;
  scene.camera.cy_px = 120;
  scene.camera.mount = Pose2{};
  return scene;
}

// Largest distance, in pixels, between where two relative poses put the frame's corners.
double CornerErrorPx(const Pose2& estimate, const Pose2& truth, const geometry::CameraModel& c) {
  double worst = 0.0;
  for (const Eigen::Vector2d& corner : geometry::FootprintInGround(c)) {
    worst = std::max(worst, (estimate * corner - truth * corner).norm() / c.resolution_m);
  }
  return worst;
}

geometry::PoseWithCovariance Prediction(const Pose2& truth, double dx_px, double dy_px,
                                        double dtheta_rad, double res) {
  return {{truth.x + dx_px * res, truth.y + dy_px * res, truth.theta + dtheta_rad},
          Eigen::Vector3d(std::pow(2 * res, 2), std::pow(2 * res, 2), 1e-4).asDiagonal()};
}

TEST(FrameRegistration, RecoversKnownOffsetAndRotationOfTwoViewsOfAPhoto) {
  tracking::TestScene scene = Scene();
  ASSERT_FALSE(scene.floor.empty());
  const double res = scene.camera.resolution_m;
  const Pose2 reference_pose{0.128, 0.128, 0.3};
  const Pose2 truth{31.3 * res, -17.6 * res, 0.045};  // target in reference: ~80 % overlap
  const cv::Mat reference = scene.Render(reference_pose, 1.0, 0.0);
  const cv::Mat target = scene.Render(reference_pose * truth, 0.85, 12.0);
  FrameRegistrar registrar(RegistrationOptions{}, scene.camera);
  const Result<FrameRegistration> r =
      registrar.Register(reference, target, Prediction(truth, 1.5, -1.0, 0.008, res));
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_GE(r->inliers, 10);
  EXPECT_LT(CornerErrorPx(r->relative.pose, truth, scene.camera), 0.05);
  // The stated covariance is honest: the error is within 4 sigma in each component.
  const Eigen::Vector3d error(r->relative.pose.x - truth.x, r->relative.pose.y - truth.y,
                              geometry::WrapAngle(r->relative.pose.theta - truth.theta));
  EXPECT_LT(error.dot(r->relative.covariance.inverse() * error), 16.0 * 3);
}

TEST(FrameRegistration, ResultDoesNotLeanOnThePrediction) {
  tracking::TestScene scene = Scene();
  const double res = scene.camera.resolution_m;
  const Pose2 reference_pose{0.130, 0.125, -1.2};
  const Pose2 truth{-20.2 * res, 40.7 * res, -0.03};
  const cv::Mat reference = scene.Render(reference_pose, 1.0, 0.0);
  const cv::Mat target = scene.Render(reference_pose * truth, 1.1, -5.0);
  FrameRegistrar registrar(RegistrationOptions{}, scene.camera);
  const Result<FrameRegistration> a =
      registrar.Register(reference, target, Prediction(truth, 2.0, 1.0, 0.01, res));
  const Result<FrameRegistration> b =
      registrar.Register(reference, target, Prediction(truth, -1.5, -2.0, -0.01, res));
  ASSERT_TRUE(a.ok()) << a.status().message();
  ASSERT_TRUE(b.ok()) << b.status().message();
  EXPECT_LT(CornerErrorPx(a->relative.pose, b->relative.pose, scene.camera), 0.02);
  EXPECT_LT(CornerErrorPx(a->relative.pose, truth, scene.camera), 0.05);
}

TEST(FrameRegistration, FramesThatDoNotOverlapAreRefused) {
  tracking::TestScene scene = Scene();
  const double res = scene.camera.resolution_m;
  const Pose2 reference_pose{0.128, 0.128, 0.0};
  const Pose2 truth{0.0, 330 * res, 0.0};  // one frame width and more to the side
  FrameRegistrar registrar(RegistrationOptions{}, scene.camera);
  const Result<FrameRegistration> r = registrar.Register(
      scene.Render(reference_pose, 1.0, 0.0), scene.Render(reference_pose * truth, 1.0, 0.0),
      Prediction(truth, 0.0, 0.0, 0.0, res));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kNotFound);
  EXPECT_NE(r.status().message().find("template matches agree"), std::string::npos);
}

TEST(RemovePrior, RecoversTheMeasurementFusedIntoAPosterior) {
  const geometry::PoseWithCovariance prior{{1.0, 2.0, 0.5},
                                           Eigen::Vector3d(4e-4, 9e-4, 1e-3).asDiagonal()};
  Eigen::Matrix3d measurement_cov;
  measurement_cov << 1e-6, 2e-7, 0, 2e-7, 3e-6, 1e-7, 0, 1e-7, 2e-6;
  const Eigen::Vector3d measurement(1.02, 1.97, 0.52);
  const Eigen::Matrix3d post_info = prior.covariance.inverse() + measurement_cov.inverse();
  const Eigen::Vector3d post =
      post_info.inverse() * (prior.covariance.inverse() * prior.pose.ToVector() +
                             measurement_cov.inverse() * measurement);
  const Result<geometry::PoseWithCovariance> m =
      RemovePrior(prior, {Pose2::FromVector(post), post_info.inverse()});
  ASSERT_TRUE(m.ok());
  EXPECT_LT((m->pose.ToVector() - measurement).norm(), 1e-9);
  EXPECT_LT((m->covariance - measurement_cov).norm(), 1e-12);
}

}  // namespace
}  // namespace fleetloc::mapping
