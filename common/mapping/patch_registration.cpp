// One tracker cycle per patch, no motion, from the reported pose.
#include "mapping/patch_registration.h"

namespace fleetloc::mapping {

PatchRegistrar::PatchRegistrar(mosaic::RasterSource* mosaic, tracking::TrackerOptions options)
    : mosaic_(mosaic), options_(options) {}

tracking::MosaicTracker& PatchRegistrar::TrackerFor(cv::Size size) {
  auto& tracker = trackers_[{size.width, size.height}];
  if (!tracker) {
    geometry::CameraModel camera;
    camera.width_px = size.width, camera.height_px = size.height;
    camera.cx_px = size.width / 2.0, camera.cy_px = size.height / 2.0;
    camera.resolution_m = mosaic_->layout().geo.resolution;
    camera.mount = {};  // the patch pose is camera_ground itself
    tracker = std::make_unique<tracking::MosaicTracker>(options_, camera, mosaic_);
  }
  return *tracker;
}

Registration PatchRegistrar::Register(const Patch& patch) {
  tracking::MosaicTracker& tracker = TrackerFor(patch.image.size());
  tracker.Reset({patch.pose, patch.covariance}, geometry::Pose2{});
  const tracking::FrameResult result = tracker.Track(patch.image, 0.0, geometry::Pose2{});
  Registration registration;
  registration.registered = result.state == tracking::LockState::kTracking;
  registration.inliers = result.inliers;
  registration.pose = registration.registered ? result.base_in_map.pose : patch.pose;
  registration.covariance =
      registration.registered ? result.base_in_map.covariance : patch.covariance;
  return registration;
}

}  // namespace fleetloc::mapping
