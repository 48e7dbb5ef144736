// Test helper (sim tests only): the small camera the simulator tests render with.
#pragma once

#include "geometry/camera_model.h"

namespace fleetloc::sim::testing {

constexpr double kResolutionM = 0.0005;  // the test photos' floor resolution

// A 128×96 camera at kResolutionM, mounted 0.40 m ahead of base_link.
inline geometry::CameraModel SmallCamera() {
  geometry::CameraModel camera;
  camera.width_px = 128;
  camera.height_px = 96;
  camera.cx_px = 64.0;
  camera.cy_px = 48.0;
  camera.resolution_m = kResolutionM;
  camera.mount = {0.40, 0.0, 0.0};
  return camera;
}

}  // namespace fleetloc::sim::testing
