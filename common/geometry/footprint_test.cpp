// Tests for camera footprints: outline per docs/formats.md
#include "geometry/footprint.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::geometry {
namespace {

CameraModel TenByEightCamera() {
  CameraModel camera;
  camera.width_px = 10;
  camera.height_px = 8;
  camera.cx_px = 5;
  camera.cy_px = 4;
  camera.resolution_m = 0.1;
  return camera;
}

TEST(Footprint, OutlineIsTheImageRectangleInCameraGround) {
  const ConvexPolygon ground = FootprintInGround(TenByEightCamera());
  ASSERT_EQ(ground.size(), 4u);
  // Image top-left (0, 0): a = +cy·res (ahead), b = +cx·res (left).
  EXPECT_NEAR(ground[0].x(), 0.4, 1e-12);
  EXPECT_NEAR(ground[0].y(), 0.5, 1e-12);
  EXPECT_NEAR(std::abs(Area(ground)), 1.0 * 0.8, 1e-12);
}

TEST(Footprint, OverlapOfAFootprintShiftedByAQuarterOfItsWidth) {
  const ConvexPolygon ground = FootprintInGround(TenByEightCamera());
  const ConvexPolygon a = PlaceFootprint(ground, {1.0, 2.0, M_PI / 2});
  // The camera's b axis (image width, 1.0 m) points along -x in map at theta = 90°.
  const ConvexPolygon b = PlaceFootprint(ground, {1.25, 2.0, M_PI / 2});
  EXPECT_NEAR(OverlapFraction(a, b), 0.75, 1e-12);
  EXPECT_NEAR(OverlapFraction(a, PlaceFootprint(ground, {5.0, 2.0, 0.0})), 0.0, 1e-12);
  EXPECT_EQ(OverlapFraction({}, a), 0.0);
}

}  // namespace
}  // namespace fleetloc::geometry
