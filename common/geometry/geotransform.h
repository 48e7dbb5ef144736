// The mosaic raster ↔ map transform (docs/formats.md, GDAL geotransform convention).
#pragma once

#include <Eigen/Core>

namespace fleetloc::geometry {

struct Geotransform {
  double origin_x = 0.0;    // map x of the top-left corner of pixel (0, 0), metres
  double origin_y = 0.0;    // map y of that corner, metres
  double resolution = 0.0;  // metres per pixel at level 0

  // Level-0 continuous pixel coordinates (u, v) → map (x, y).
  Eigen::Vector2d PixelToMap(const Eigen::Vector2d& uv) const {
    return {origin_x + uv.x() * resolution, origin_y - uv.y() * resolution};
  }
  // Map (x, y) → level-0 continuous pixel coordinates.
  Eigen::Vector2d MapToPixel(const Eigen::Vector2d& xy) const {
    return {(xy.x() - origin_x) / resolution, (origin_y - xy.y()) / resolution};
  }
  // The transform of pyramid level k (resolution · 2^k, same origin).
  Geotransform AtLevel(int level) const {
    return {origin_x, origin_y, resolution * static_cast<double>(1 << level)};
  }
};

}  // namespace fleetloc::geometry
