// Frame ↔ mosaic affine from three mapped points (the composition is exactly affine).
#include "tracking/frame_mosaic_warp.h"

#include <Eigen/LU>

namespace fleetloc::tracking {

FrameMosaicWarp FrameMosaicWarp::For(const geometry::Pose2& camera_in_map,
                                     const geometry::CameraModel& camera,
                                     const geometry::Geotransform& geo) {
  auto map = [&](double u, double v) {
    return geo.MapToPixel(camera_in_map * camera.PixelToGround({u, v}));
  };
  FrameMosaicWarp warp;
  warp.offset = map(0, 0);
  warp.linear.col(0) = map(1, 0) - warp.offset;
  warp.linear.col(1) = map(0, 1) - warp.offset;
  return warp;
}

FrameMosaicWarp FrameMosaicWarp::Inverse() const {
  FrameMosaicWarp inverse;
  inverse.linear = linear.inverse();
  inverse.offset = -inverse.linear * offset;
  return inverse;
}

geometry::ConvexPolygon MosaicInFrame(const FrameMosaicWarp& to_mosaic, double width_px,
                                      double height_px, double inset_px) {
  const FrameMosaicWarp to_frame = to_mosaic.Inverse();
  geometry::ConvexPolygon polygon;
  for (const auto& corner :
       geometry::Rectangle(inset_px, inset_px, width_px - inset_px, height_px - inset_px)) {
    polygon.push_back(to_frame(corner));
  }
  return polygon;
}

}  // namespace fleetloc::tracking
