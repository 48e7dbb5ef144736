// One tracker cycle per patch, no motion, from the reported pose.
#include "mapping/patch_registration.h"

#include "tracking/predicted_view.h"

namespace fleetloc::mapping {
namespace {

geometry::CameraModel PatchCamera(cv::Size size, double resolution_m) {
  geometry::CameraModel camera;
  camera.width_px = size.width;
  camera.height_px = size.height;
  camera.cx_px = size.width / 2.0;
  camera.cy_px = size.height / 2.0;
  camera.resolution_m = resolution_m;
  camera.mount = {};  // the patch pose is camera_ground itself
  return camera;
}

}  // namespace

cv::Mat MosaicUnderPatch(mosaic::RasterSource* mosaic, cv::Size size, const geometry::Pose2& pose) {
  const geometry::CameraModel camera = PatchCamera(size, mosaic->layout().geo.resolution);
  const auto warp = tracking::FrameMosaicWarp::For(pose, camera, mosaic->layout().geo);
  return tracking::RenderPredictedView(mosaic, {0, 0, size.width, size.height}, warp, 0);
}

PatchRegistrar::PatchRegistrar(mosaic::RasterSource* mosaic, tracking::TrackerOptions options)
    : mosaic_(mosaic), options_(tracking::CountingTemplateInliers(options)) {}

tracking::MosaicTracker& PatchRegistrar::TrackerFor(cv::Size size) {
  auto& tracker = trackers_[{size.width, size.height}];
  if (!tracker) {
    tracker = std::make_unique<tracking::MosaicTracker>(
        options_, PatchCamera(size, mosaic_->layout().geo.resolution), mosaic_);
  }
  return *tracker;
}

Registration PatchRegistrar::Register(const Patch& patch, const Eigen::Matrix3d& prior) {
  tracking::MosaicTracker& tracker = TrackerFor(patch.image.size());
  tracker.Reset({patch.pose, prior}, geometry::Pose2{});
  const tracking::FrameResult result = tracker.Track(patch.image, 0.0, geometry::Pose2{});
  Registration registration;
  registration.registered = result.state == tracking::LockState::kTracking;
  registration.inliers = result.inliers;
  registration.rms_residual_px = result.rms_residual_px;
  registration.pose = registration.registered ? result.base_in_map.pose : patch.pose;
  registration.covariance = registration.registered ? result.base_in_map.covariance : prior;
  return registration;
}

}  // namespace fleetloc::mapping
