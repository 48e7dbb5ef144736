// Registration of a vehicle's floor patch against the current mosaic: one cycle of the mosaic
// tracker (texture-and-spread selection, coarse-to-fine NCC, Kalman update with outlier
// rejection) with the patch as the frame, started at the reported pose with its covariance and no
// motion. Trackers are kept per patch size, so the normalized mosaic tiles are computed once.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <utility>

#include "geometry/pose2.h"
#include "mosaic/raster_source.h"
#include "tracking/mosaic_tracker.h"

namespace fleetloc::mapping {

// A rectified floor image (CV_8UC1 at the mosaic's level-0 resolution) and the pose of its
// camera_ground frame (image centre) in map, with covariance, as its sender reported them.
struct Patch {
  cv::Mat image;
  geometry::Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double quality = 0;      // the sender's own 0..1 (ranks admitted patches, never admits)
  std::string vehicle_id;  // who sent it (reputation, corroboration, reports)
};

struct Registration {
  bool registered = false;  // enough inlier correspondences
  geometry::Pose2 pose;     // refined when registered, else the reported pose
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  int inliers = 0;
  double rms_residual_px = 0;  // of the kept correspondences
};

// The mosaic as a patch of `size` whose camera_ground (image centre) is at `pose` sees it, in the
// patch's pixel grid (CV_8UC1; 0 outside the mosaic).
cv::Mat MosaicUnderPatch(mosaic::RasterSource* mosaic, cv::Size size, const geometry::Pose2& pose);

class PatchRegistrar {
 public:
  PatchRegistrar(mosaic::RasterSource* mosaic, tracking::TrackerOptions options);
  // One tracker cycle from `patch.pose` with `prior` as its covariance (the search window).
  Registration Register(const Patch& patch, const Eigen::Matrix3d& prior);
  // The same with the patch's own covariance as the prior.
  Registration Register(const Patch& patch) { return Register(patch, patch.covariance); }

 private:
  tracking::MosaicTracker& TrackerFor(cv::Size size);
  mosaic::RasterSource* mosaic_;
  tracking::TrackerOptions options_;
  std::map<std::pair<int, int>, std::unique_ptr<tracking::MosaicTracker>> trackers_;
};

}  // namespace fleetloc::mapping
