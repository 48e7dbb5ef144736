// A camera frame's footprint on the floor: its outline in camera_ground and placed in map
// (docs/formats.md). Shared by the simulator's route fitting and the mapping run's
// overlap tests.
#pragma once

#include "geometry/camera_model.h"
#include "geometry/convex_polygon.h"
#include "geometry/pose2.h"

namespace fleetloc::geometry {

// The camera frame's outline (its four image corners) in camera_ground metres.
ConvexPolygon FootprintInGround(const CameraModel& camera);

// The footprint outline placed in map by the camera_ground pose; counter-clockwise.
ConvexPolygon PlaceFootprint(const ConvexPolygon& footprint_ground, const Pose2& camera_in_map);

// Share of footprint a's area that footprint b covers (0 when either is degenerate).
double OverlapFraction(const ConvexPolygon& a, const ConvexPolygon& b);

}  // namespace fleetloc::geometry
