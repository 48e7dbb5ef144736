// A 3-D corridor for testing forward-camera landmark detection: walls, door openings, cupboards and
// a pillar made of convex solids standing on the floor, whose floor-level vertical corners are the
// landmark map (paper 001 §6.1), plus clutter that is not in the map (posters, a rail, a bin with
// slanted sides, stains). Geometry is in the `map` frame, z up, floor at z = 0; rays are cast
// against it in sim/corridor_raycast.h.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "base/status.h"

namespace fleetloc::sim {

// A half-space normal · p <= offset (normal of unit length, pointing out of the solid).
struct HalfSpace {
  Eigen::Vector3d normal;
  double offset = 0.0;
};

// A convex solid: the intersection of its half-spaces.
struct Solid {
  std::vector<HalfSpace> faces;
  double albedo = 0.7;     // reflectance, 0..1
  bool baseboard = false;  // darker strip along the floor on faces along the corridor (±y)
};

// A dark blob painted on surfaces: albedo × (1 - darkening) within `radius_m` of `center`.
struct Stain {
  Eigen::Vector3d center;
  double radius_m = 0.1;
  double darkening = 0.5;
};

struct CorridorScene {
  std::vector<Solid> solids;
  std::vector<Stain> stains;
  std::vector<Eigen::Vector2d> landmarks;  // floor-level vertical corners (map), the map to fit
  double floor_albedo = 0.45;
  double floor_tile_m = 0.6;  // square floor tiles with darker grout lines
  double ceiling_height_m = 2.5;
  double ceiling_albedo = 0.85;
};

// The corridor's layout; positions are jittered by the seed so that scenes differ.
struct CorridorSceneOptions {
  double length_m = 16.0;  // along +x from x = 0
  double width_m = 2.4;    // centred on y = 0
  double jitter_m = 0.4;   // uniform ± on door, cupboard, alcove and pillar positions
  int stains = 30;
  std::uint64_t seed = 1;
};

// InvalidInput naming the field for a non-positive size or jitter beyond what the layout allows.
Status Validate(const CorridorSceneOptions& options);

// The corridor described in corridor_scene.cpp (aborts on invalid options: validate first).
CorridorScene BuildCorridorScene(const CorridorSceneOptions& options);

}  // namespace fleetloc::sim
