// The corridor scene and its forward-camera renderer: ray hits at known distances, landmarks on
// solid corners, visibility (occlusion, field of view) and rendered edges where the truth says.
#include "sim/corridor_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "sim/corridor_raycast.h"
#include "sim/forward_renderer.h"

namespace fleetloc::sim {
namespace {

CorridorSceneOptions Unjittered() {
  CorridorSceneOptions options;
  options.jitter_m = 0.0;
  options.stains = 0;
  return options;
}

mapmatch::ForwardCamera TestCamera() {
  mapmatch::ForwardCameraParams p;
  p.K = {520, 0, 320, 0, 520, 240, 0, 0, 1};
  p.dist = {-0.08, 0.01, 0, 0, 0};
  p.mount = {.x_m = 0.45, .y_m = 0, .height_m = 1.0, .yaw_rad = 0, .pitch_rad = 0.25};
  return mapmatch::ForwardCamera::Create(p).value();
}

TEST(CorridorScene, RaysHitTheWallFloorAndCeilingAtKnownDistances) {
  const CorridorScene scene = BuildCorridorScene(Unjittered());
  const Eigen::Vector3d origin(7.5, 0.2, 1.0);  // between the posters, facing plain wall
  const std::optional<RayHit> left = CastRay(scene, origin, Eigen::Vector3d::UnitY());
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(left->distance_m, 1.0, 1e-12);
  EXPECT_EQ(left->normal, -Eigen::Vector3d::UnitY());
  EXPECT_GT(left->albedo, 0.0);
  const std::optional<RayHit> down = CastRay(scene, origin, -Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(down.has_value());
  EXPECT_NEAR(down->distance_m, 1.0, 1e-12);
  EXPECT_NEAR(*HitDistance(scene, origin, Eigen::Vector3d::UnitZ()), 1.5, 1e-12);
  EXPECT_NEAR(*HitDistance(scene, origin, Eigen::Vector3d::UnitX()), 16.0 - 7.5, 1e-12)
      << "the end wall";
}

TEST(CorridorScene, RaysInsideADoorOpeningHitTheRecessedLeaf) {
  const CorridorScene scene = BuildCorridorScene(Unjittered());
  // Door A spans x in [2.8, 3.7] on the left wall (y = 1.2); its leaf is 0.1 m behind.
  EXPECT_NEAR(*HitDistance(scene, {3.25, 0.0, 1.0}, Eigen::Vector3d::UnitY()), 1.3, 1e-12);
  EXPECT_NEAR(*HitDistance(scene, {3.25, 0.0, 2.3}, Eigen::Vector3d::UnitY()), 1.2, 1e-12)
      << "the lintel above the door";
}

TEST(CorridorScene, EveryLandmarkIsAFloorCornerOfSomeSolid) {
  const CorridorScene scene = BuildCorridorScene({});
  ASSERT_GE(scene.landmarks.size(), 30u);
  for (const Eigen::Vector2d& landmark : scene.landmarks) {
    // A corner lies on the boundary of a solid: on at least two of its faces at floor level.
    bool corner = false;
    for (const Solid& solid : scene.solids) {
      int on_faces = 0;
      bool inside = true;
      for (const HalfSpace& face : solid.faces) {
        const double d =
            face.normal.dot(Eigen::Vector3d(landmark.x(), landmark.y(), 0.0)) - face.offset;
        inside = inside && d <= 1e-9;
        on_faces += std::abs(d) <= 1e-9 && face.normal.z() == 0.0;
      }
      corner = corner || (inside && on_faces >= 2);
    }
    EXPECT_TRUE(corner) << landmark.transpose();
  }
}

TEST(CorridorScene, SeedsMoveTheFeatures) {
  CorridorSceneOptions options;
  const CorridorScene a = BuildCorridorScene(options);
  options.seed = 2;
  const CorridorScene b = BuildCorridorScene(options);
  ASSERT_EQ(a.landmarks.size(), b.landmarks.size());
  EXPECT_NE(a.landmarks[4], b.landmarks[4]);
}

TEST(CorridorScene, InvalidOptionsNameTheField) {
  CorridorSceneOptions options;
  options.jitter_m = 0.6;
  EXPECT_NE(Validate(options).message().find("jitter_m"), std::string::npos);
  options = {};
  options.width_m = std::nan("");
  EXPECT_NE(Validate(options).message().find("width_m"), std::string::npos);
}

TEST(VisibleLandmarks, HiddenAndOutOfViewCornersAreLeftOut) {
  const CorridorScene scene = BuildCorridorScene(Unjittered());
  const mapmatch::ForwardCamera camera = TestCamera();
  // Looking down the corridor from its start: the cupboard (x 3.4..4.6, right wall) hides its
  // own back corners' far side and the door behind it is out of view or hidden.
  const geometry::Pose2 pose{1.0, 0.0, 0.0};
  const ForwardRenderer renderer(camera, {.supersample = 1});
  const std::vector<VisibleLandmark> visible = renderer.VisibleLandmarks(scene, pose);
  const auto seen = [&](const Eigen::Vector2d& corner) {
    return std::any_of(visible.begin(), visible.end(),
                       [&](const VisibleLandmark& v) { return (v.map - corner).norm() < 1e-9; });
  };
  EXPECT_TRUE(seen({3.4, -0.6})) << "the cupboard's near front corner";
  EXPECT_TRUE(seen({4.6, -0.6})) << "its far front corner, a silhouette against the wall";
  EXPECT_FALSE(seen({4.6, -1.2})) << "its far back corner is behind the cupboard";
  EXPECT_FALSE(seen({0.0, 1.2})) << "behind the camera";
  for (const VisibleLandmark& v : visible) {
    EXPECT_NEAR((camera.Project({v.base.x(), v.base.y(), 0.0}).value() - v.pixel).norm(), 0, 1e-9);
    EXPECT_NEAR((pose * v.base - v.map).norm(), 0, 1e-12);
    EXPECT_GT(v.contrast_dn, 0.0);
  }
}

// Rendering: at each visible landmark the image shows an edge (the two faces differ) just above
// the foot, and the same seed gives the same image.
TEST(ForwardRenderer, VisibleCornersShowAsEdgesAndRenderingIsDeterministic) {
  const CorridorScene scene = BuildCorridorScene({});
  const mapmatch::ForwardCamera camera = TestCamera();
  const ForwardRenderer renderer(camera, {});
  const geometry::Pose2 pose{1.5, 0.2, 0.1};
  const cv::Mat image = renderer.Render(scene, pose, 7);
  ASSERT_EQ(image.type(), CV_8UC1);
  ASSERT_EQ(image.size(), camera.image_size());
  EXPECT_EQ(cv::norm(image, renderer.Render(scene, pose, 7), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(image, renderer.Render(scene, pose, 8), cv::NORM_INF), 0.0);
  cv::Mat smooth;
  cv::GaussianBlur(image, smooth, cv::Size(), 1.5);
  int with_edge = 0, near = 0;
  for (const VisibleLandmark& v : renderer.VisibleLandmarks(scene, pose)) {
    if (v.range_m > 6.0) continue;
    ++near;
    // 0.15 m up the edge, 4 px either side of it.
    const Eigen::Vector2d up = camera.Project({v.base.x(), v.base.y(), 0.15}).value();
    const auto at = [&](double du) {
      return smooth.at<uchar>(static_cast<int>(std::lround(up.y())),
                              static_cast<int>(std::lround(up.x() + du)));
    };
    with_edge += std::abs(at(4) - at(-4)) >= 10;
  }
  EXPECT_GE(near, 5);
  EXPECT_EQ(with_edge, near);
}

}  // namespace
}  // namespace fleetloc::sim
