// Test helpers shared by the dense place search tests: the stress suite's plain-concrete
// photograph (1024 × 1024, 0.5 mm/px) and a 320×240 camera mounted 0.40 m ahead.
#pragma once

#include <gtest/gtest.h>

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

inline geometry::CameraModel SmallCamera() {
  return sim::DefaultSimCameraModel(320, 240, kResolutionM);
}

}  // namespace fleetloc::relocalization::testing
