// Test helpers shared by the dense place search tests: the stress suite's plain-concrete
// photograph (1024 × 1024, 0.5 mm/px), a 320×240 camera mounted 0.40 m ahead, and a floor with a
// cloned patch.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include "geometry/camera_model.h"
#include "sim/run_simulator.h"

namespace fleetloc::relocalization::testing {

constexpr double kResolutionM = 0.0005;

inline cv::Mat PlainConcrete() {
  cv::Mat photo = cv::imread(FLEETLOC_SOURCE_DIR "/data/stress_floors/plain_concrete_g4.jpg",
                             cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(photo.empty());
  return photo;
}

// A floor photograph's geotransform: kResolutionM a pixel, the origin at its top-left corner.
inline geometry::Geotransform GeoOf(const cv::Mat& photo) {
  return {0.0, photo.rows * kResolutionM, kResolutionM};
}

inline geometry::CameraModel SmallCamera() {
  return sim::DefaultSimCameraModel(320, 240, kResolutionM);
}

// The photograph with its 400 × 400 px square at (60, 60) copied to (560, 560), as a
// clone-stamped floor photograph repeats a patch of itself; the copy's offset in map metres.
struct ClonedPatch {
  static constexpr int kSidePx = 400, kFromPx = 60, kToPx = 560;
  cv::Mat photo;
  Eigen::Vector2d offset_m{(kToPx - kFromPx) * kResolutionM, -(kToPx - kFromPx) * kResolutionM};
};

inline ClonedPatch WithClonedPatch(const cv::Mat& photo) {
  ClonedPatch c;
  c.photo = photo.clone();
  const cv::Size side(ClonedPatch::kSidePx, ClonedPatch::kSidePx);
  photo(cv::Rect(cv::Point(ClonedPatch::kFromPx, ClonedPatch::kFromPx), side))
      .copyTo(c.photo(cv::Rect(cv::Point(ClonedPatch::kToPx, ClonedPatch::kToPx), side)));
  return c;
}

// The camera pose, heading θ, whose frame centre falls on continuous pixel (u, v) of a floor
// `rows` pixels tall (origin at its top-left corner, kResolutionM a pixel).
inline geometry::Pose2 CameraCentredAt(const geometry::CameraModel& camera, double u, double v,
                                       int rows, double theta) {
  const Eigen::Vector2d centre_ground =
      camera.PixelToGround({0.5 * camera.width_px, 0.5 * camera.height_px});
  const Eigen::Vector2d xy = Eigen::Vector2d(u * kResolutionM, (rows - v) * kResolutionM) -
                             Eigen::Rotation2Dd(theta) * centre_ground;
  return {xy.x(), xy.y(), theta};
}

}  // namespace fleetloc::relocalization::testing
