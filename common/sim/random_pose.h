// Random vehicle poses over a floor for relocalization trials: the camera footprint centre uniform
// over the part of the floor where the whole frame fits at any heading, the heading uniform.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/camera_model.h"
#include "mosaic/raster_source.h"

namespace fleetloc::sim {

// base_link's pose in map such that camera_ground is uniform as described above. Requires a floor
// larger than the frame's diagonal both ways.
inline geometry::Pose2 RandomFullFramePose(const mosaic::MosaicLayout& floor,
                                           const geometry::CameraModel& camera,
                                           std::mt19937_64& rng) {
  const double half_diagonal_px = 0.5 * std::hypot(camera.width_px, camera.height_px) + 2.0;
  std::uniform_real_distribution<double> u(half_diagonal_px, floor.width_px - half_diagonal_px);
  std::uniform_real_distribution<double> v(half_diagonal_px, floor.height_px - half_diagonal_px);
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  const double pu = u(rng), pv = v(rng);
  const Eigen::Vector2d xy = floor.geo.PixelToMap({pu, pv});
  return geometry::Pose2{xy.x(), xy.y(), heading(rng)} * camera.mount.Inverse();
}

}  // namespace fleetloc::sim
