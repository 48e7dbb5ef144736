// Camera footprints on the floor.
#include "geometry/footprint.h"

#include <cmath>

namespace fleetloc::geometry {

ConvexPolygon FootprintInGround(const CameraModel& camera) {
  const double w = camera.width_px, h = camera.height_px;
  return {camera.PixelToGround({0, 0}), camera.PixelToGround({0, h}), camera.PixelToGround({w, h}),
          camera.PixelToGround({w, 0})};
}

ConvexPolygon PlaceFootprint(const ConvexPolygon& footprint_ground, const Pose2& camera_in_map) {
  ConvexPolygon placed;
  for (const auto& corner : footprint_ground) placed.push_back(camera_in_map * corner);
  return CounterClockwise(placed);
}

double OverlapFraction(const ConvexPolygon& a, const ConvexPolygon& b) {
  const double area = std::abs(Area(a));
  if (!(area > 0.0) || b.size() < 3) return 0.0;
  return Area(ClipConvex(a, b)) / area;
}

}  // namespace fleetloc::geometry
