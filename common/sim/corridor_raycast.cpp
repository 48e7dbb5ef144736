// Ray casting against the corridor (see corridor_raycast.h): the slab method per convex solid,
// the floor and ceiling planes, and a procedural texture evaluated at the hit point.
#include "sim/corridor_raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/random.h"

namespace fleetloc::sim {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kBaseboardHeight = 0.1;
constexpr double kGroutWidth = 0.006;

struct SurfaceHit {
  double distance = kInfinity;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  const Solid* solid = nullptr;  // null for the floor and the ceiling
};

// Where the ray enters a convex solid (Cyrus–Beck clipping of the ray against each half-space).
void HitSolid(const Solid& solid, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
              SurfaceHit* nearest) {
  double enter = 0.0, exit = nearest->distance;
  const Eigen::Vector3d* enter_normal = nullptr;
  for (const HalfSpace& face : solid.faces) {
    const double along = face.normal.dot(direction);
    const double room = face.offset - face.normal.dot(origin);  // >= 0 when origin is inside
    if (along == 0.0) {
      if (room < 0.0) return;
      continue;
    }
    const double t = room / along;
    if (along < 0.0) {
      if (t > enter) {
        enter = t;
        enter_normal = &face.normal;
      }
    } else {
      exit = std::min(exit, t);
    }
    if (enter > exit) return;
  }
  if (enter_normal == nullptr || enter >= nearest->distance) return;
  *nearest = {enter, *enter_normal, &solid};
}

// A horizontal plane z = height seen from the side `normal_z` points to.
void HitPlane(double height, double normal_z, const Eigen::Vector3d& origin,
              const Eigen::Vector3d& direction, SurfaceHit* nearest) {
  if (direction.z() * normal_z >= 0.0) return;
  const double t = (height - origin.z()) / direction.z();
  if (t > 0.0 && t < nearest->distance) *nearest = {t, Eigen::Vector3d(0, 0, normal_z), nullptr};
}

SurfaceHit Nearest(const CorridorScene& scene, const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& direction) {
  SurfaceHit nearest;
  HitPlane(0.0, 1.0, origin, direction, &nearest);
  HitPlane(scene.ceiling_height_m, -1.0, origin, direction, &nearest);
  for (const Solid& solid : scene.solids) HitSolid(solid, origin, direction, &nearest);
  return nearest;
}

// A uniform value in [0, 1) per integer lattice point.
double LatticeValue(std::int64_t i, std::int64_t j, std::int64_t k) {
  const std::uint64_t h = SplitMix64(static_cast<std::uint64_t>(i) * 73856093ULL ^
                                     static_cast<std::uint64_t>(j) * 19349663ULL ^
                                     static_cast<std::uint64_t>(k) * 83492791ULL);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

// Smooth value noise in [0, 1): trilinear interpolation of lattice values with smoothstep weights.
double ValueNoise(const Eigen::Vector3d& p) {
  const Eigen::Vector3d cell = p.array().floor();
  const Eigen::Vector3d f = p - cell;
  const Eigen::Vector3d w = f.array().square() * (3.0 - 2.0 * f.array());
  const auto i = static_cast<std::int64_t>(cell.x()), j = static_cast<std::int64_t>(cell.y()),
             k = static_cast<std::int64_t>(cell.z());
  double value = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    const double weight =
        (dx ? w.x() : 1 - w.x()) * (dy ? w.y() : 1 - w.y()) * (dz ? w.z() : 1 - w.z());
    value += weight * LatticeValue(i + dx, j + dy, k + dz);
  }
  return value;
}

// Floor tiles: per-tile brightness and darker grout lines.
double FloorAlbedo(const CorridorScene& scene, const Eigen::Vector3d& p) {
  const double tile = scene.floor_tile_m;
  const double ti = std::floor(p.x() / tile), tj = std::floor(p.y() / tile);
  double albedo =
      scene.floor_albedo *
      (0.92 + 0.16 * LatticeValue(static_cast<std::int64_t>(ti), static_cast<std::int64_t>(tj), 7));
  const double gx = p.x() - ti * tile, gy = p.y() - tj * tile;
  if (std::min({gx, gy, tile - gx, tile - gy}) < kGroutWidth / 2) albedo *= 0.8;
  return albedo;
}

double StainFactor(const CorridorScene& scene, const Eigen::Vector3d& p) {
  double factor = 1.0;
  for (const Stain& stain : scene.stains) {
    const double r = (p - stain.center).norm() / stain.radius_m;
    if (r < 1.0) factor *= 1.0 - stain.darkening * (1.0 - r * r);
  }
  return factor;
}

double TexturedAlbedo(const CorridorScene& scene, const SurfaceHit& hit, const Eigen::Vector3d& p) {
  double albedo = scene.ceiling_albedo;
  if (hit.solid != nullptr) {
    albedo = hit.solid->albedo;
    // Along the corridor's walls (±y faces) only: door reveals have none.
    const bool along_corridor = std::abs(hit.normal.y()) > 0.5;
    if (hit.solid->baseboard && along_corridor && p.z() < kBaseboardHeight) {
      albedo = std::min(1.0, albedo * 1.25);  // white skirting
    }
  } else if (hit.normal.z() > 0) {
    albedo = FloorAlbedo(scene, p);
  }
  // Coarse mottling and fine grain, as on painted or worn surfaces.
  albedo *= 0.88 + 0.24 * ValueNoise(p * 5.0);
  albedo *= 0.94 + 0.12 * ValueNoise(p * 60.0 + Eigen::Vector3d(17.0, 3.0, 5.0));
  return albedo * StainFactor(scene, p);
}

}  // namespace

std::optional<RayHit> CastRay(const CorridorScene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction) {
  const SurfaceHit hit = Nearest(scene, origin, direction);
  if (hit.distance == kInfinity) return std::nullopt;
  const Eigen::Vector3d point = origin + hit.distance * direction;
  return RayHit{hit.distance, hit.normal, TexturedAlbedo(scene, hit, point)};
}

std::optional<double> HitDistance(const CorridorScene& scene, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction) {
  const SurfaceHit hit = Nearest(scene, origin, direction);
  if (hit.distance == kInfinity) return std::nullopt;
  return hit.distance;
}

}  // namespace fleetloc::sim
