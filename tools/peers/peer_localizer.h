// PeerLocalizer: the common frame of the OpenCV-based peers fleetloc is benchmarked against. For
// fairness every peer predicts exactly as fleetloc does (its own last estimate ⊕ the odometry
// increment, same noise model), renders the predicted mosaic view around the frame with the same
// code as fleetloc's matcher, and turns its frame → view registration into a camera pose with
// fleetloc's Kalman update. Only the registration differs; a failed one coasts.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "geometry/camera_model.h"
#include "mosaic/raster_source.h"
#include "tracking/frame_localizer.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/internal_estimate.h"
#include "tracking/pose_update.h"
#include "tracking/tracker_options.h"

namespace fleetloc::peers {

struct PeerOptions {
  tracking::OdometryNoiseOptions odometry;  // fleetloc's model and defaults: the same prediction
  // 1-sigma of each of the five frame points that carry a registration into the pose update
  // (≈ 0.45 × this for the frame's position). It should match the method's real accuracy: too
  // large and the prior drags good registrations back towards odometry. Each peer's
  // DefaultOptions() sets it from its accuracy measured in peers_test.
  double measurement_sigma_px = 0.25;
  int max_coasting_frames = 50;  // fleetloc's default: after this many frames without a fix, lost
  // Plausibility gates on the frame → view similarity: the prediction is within a few degrees
  // and the scale is fixed by calibration, so anything beyond these is a false registration.
  double max_rotation_rad = 0.2;
  double max_scale_error = 0.1;
};

// The defaults above with another measurement sigma (each peer's DefaultOptions()).
inline PeerOptions WithMeasurementSigma(double measurement_sigma_px) {
  PeerOptions options;
  options.measurement_sigma_px = measurement_sigma_px;
  return options;
}

// A registration of the frame onto the predicted view, in OpenCV pixel indices (pixel centres
// at integers): view index = frame_to_view · (frame index, 1).
struct Registration {
  cv::Matx23d frame_to_view = cv::Matx23d(1, 0, 0, 0, 1, 0);
  int matches = 0;               // correspondences measured (FrameResult::templates)
  int inliers = 0;               // correspondences consistent with the transform
  double rms_residual_px = 0.0;  // of the inliers, where meaningful
};

class PeerLocalizer : public tracking::FrameLocalizer {
 public:
  void Reset(const geometry::PoseWithCovariance& base_in_map, const geometry::Pose2& odom) override;
  // Predicts, renders the view (frame grown by view_margin_px on each side), registers, and
  // solves the camera pose; coasts on the prediction when registration fails or is implausible.
  // `frame` must be CV_8UC1 of the camera's size; Reset() must have been called.
  tracking::FrameResult Track(const cv::Mat& frame, double t, const geometry::Pose2& odom) override;
  tracking::FrameResult Coast(double t, const geometry::Pose2& odom) override;

 protected:
  // `mosaic` must outlive the peer.
  PeerLocalizer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                int view_margin_px, const PeerOptions& options);

  // Registers `frame` onto `view` (the predicted mosaic view, CV_8UC1, frame size + 2 × margin;
  // the prediction places frame index p at view index p + margin). Returns nothing on failure;
  // a cv::Exception thrown here is caught by Track() and also counts as a failure.
  virtual std::optional<Registration> Register(const cv::Mat& frame, const cv::Mat& view) = 0;

 private:
  std::optional<Registration> TryRegister(const cv::Mat& frame, const cv::Mat& view);
  bool Plausible(const Registration& registration, const cv::Size& view_size) const;
  tracking::PoseUpdate SolvePose(const geometry::PoseWithCovariance& prior,
                                 const Registration& registration, const cv::Point& view_origin,
                                 const tracking::FrameMosaicWarp& warp) const;
  tracking::FrameResult Finish(double t, tracking::LockState state);

  geometry::CameraModel camera_;
  mosaic::RasterSource* mosaic_;
  int view_margin_px_;
  PeerOptions options_;
  tracking::InternalEstimate estimate_;  // camera_ground in map: the peer's own estimate
  int coasting_frames_ = 0;
  tracking::LockState state_ = tracking::LockState::kLost;
};

}  // namespace fleetloc::peers
