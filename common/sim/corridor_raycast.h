// Ray casting against a CorridorScene: the first surface hit along a ray with its normal and
// textured albedo (value-noise texture, floor tiles with grout, wall baseboards, stains).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "sim/corridor_scene.h"

namespace fleetloc::sim {

// A ray's first hit: distance along the (unit) direction, the surface's outward normal and
// textured albedo at the hit point.
struct RayHit {
  double distance_m = 0.0;
  Eigen::Vector3d normal;
  double albedo = 0.0;
};

// The nearest surface (solid, floor or ceiling) along origin + t · direction, t > 0; nullopt when
// the ray escapes. `direction` must have unit length.
std::optional<RayHit> CastRay(const CorridorScene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction);

// The distance to the nearest surface only, without texturing (for visibility checks).
std::optional<double> HitDistance(const CorridorScene& scene, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction);

}  // namespace fleetloc::sim
