// The affine map between a frame's continuous pixel coordinates and the mosaic's level-0
// continuous pixel coordinates for a camera pose (camera_ground in map): frame pixel → ground
// (docs/formats.md) → map (pose) → mosaic pixel (docs/formats.md). Both use pixel centres at i +
// 0.5.
#pragma once

#include <Eigen/Core>

#include "geometry/camera_model.h"
#include "geometry/convex_polygon.h"
#include "geometry/geotransform.h"

namespace fleetloc::tracking {

struct FrameMosaicWarp {
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();  // mosaic = linear · frame + offset
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();

  static FrameMosaicWarp For(const geometry::Pose2& camera_in_map,
                             const geometry::CameraModel& camera,
                             const geometry::Geotransform& geo);
  Eigen::Vector2d operator()(const Eigen::Vector2d& frame_px) const {
    return linear * frame_px + offset;
  }
  FrameMosaicWarp Inverse() const;
  // The same map between pyramid level `level` of the frame and of the mosaic (both halved per
  // level, INTER_AREA-style, so continuous coordinates scale by exactly 2^-level).
  FrameMosaicWarp AtLevel(int level) const {
    return {linear, offset / static_cast<double>(1 << level)};
  }
};

// The mosaic's level-0 area [inset, width − inset] × [inset, height − inset] in the frame's pixel
// coordinates, for the frame → mosaic map `to_mosaic`.
geometry::ConvexPolygon MosaicInFrame(const FrameMosaicWarp& to_mosaic, double width_px,
                                      double height_px, double inset_px = 0.0);

}  // namespace fleetloc::tracking
