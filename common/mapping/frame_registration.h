// Frame-to-frame registration for mapping (docs/architecture.md: "register overlapping frames with
// the same correlation machinery"): one camera frame is treated as a small mosaic and the other is
// tracked over it by the mosaic tracker itself — texture-scored, spread feature selection,
// normalized templates, NCC with sub-pixel peaks and quality gates, coarse to fine, and the Kalman
// pose update with outlier rejection. The result is the relative SE(2) pose of the two
// camera_ground frames with the covariance of the image measurement alone.
#pragma once

#include <opencv2/core.hpp>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "tracking/tracker_options.h"

namespace fleetloc::mapping {

// The tracker's defaults, with one extra fine pass (re-matching at the refined pose, where the
// sub-pixel peak fit is unbiased), a wider largest search for loop closures, and no
// full-resolution polish: a registration's covariance comes from its templates' scatter, which the
// polished pose no longer matches (measured: NEES 96 against ≤ 48 in
// FrameRegistration.RecoversKnownOffsetAndRotationOfTwoViewsOfAPhoto), and the mosaic a frame is
// registered to is another noisy frame, not a clean photograph.
tracking::TrackerOptions FramePairTrackerOptions();

struct RegistrationOptions {
  tracking::TrackerOptions tracker = FramePairTrackerOptions();
  int min_inliers = 8;                 // fewer agreeing template matches: registration fails
  double min_prior_sigma_px = 2.0;     // the prediction's 1-sigma is raised to at least this …
  double min_prior_sigma_rad = 0.004;  // … and this, so the search window is never too tight
  // The covariance is rescaled to the template residuals' own scatter (see Register), with the
  // per-template 1-sigma taken as at least this.
  double min_template_sigma_px = 0.02;
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const RegistrationOptions& options);

struct FrameRegistration {
  // camera_ground of the target frame in camera_ground of the reference frame, with the
  // covariance of the image measurement alone (the prediction's information is removed).
  geometry::PoseWithCovariance relative;
  int inliers = 0;
  double rms_residual_px = 0.0;
};

class FrameRegistrar {
 public:
  // `options` must pass Validate(); the camera's mount is ignored (frames are related directly).
  FrameRegistrar(const RegistrationOptions& options, const geometry::CameraModel& camera);

  // Registers `target` against `reference` (both CV_8UC1 of the camera's size). `predicted` is the
  // expected relative pose (target in reference) with a positive definite covariance; it places
  // the search windows (3 sigma, raised to the option minimums). The tracker weighs each template
  // match with its model sigma (measurement_sigma_px, made for a frame against a mosaic); between
  // two frames of one run the matches are often much better, so the measured covariance is scaled
  // by the residuals' own variance (rms² · n / (2n − 3) per axis over n inliers) over the model's.
  // NotFound with the reason when the frames do not overlap enough or too few matches agree.
  Result<FrameRegistration> Register(const cv::Mat& reference, const cv::Mat& target,
                                     const geometry::PoseWithCovariance& predicted) const;

 private:
  geometry::PoseWithCovariance Widened(const geometry::PoseWithCovariance& predicted) const;

  RegistrationOptions options_;
  geometry::CameraModel camera_;  // mount set to identity
};

// The measurement alone from an information-form Kalman posterior: removes the prior's
// information (posterior information − prior information) and the pull of the prior mean, exact
// for the linearized update. NotFound when what remains is not positive definite.
Result<geometry::PoseWithCovariance> RemovePrior(const geometry::PoseWithCovariance& prior,
                                                 const geometry::PoseWithCovariance& posterior);

}  // namespace fleetloc::mapping
