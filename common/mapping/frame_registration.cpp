// Frame-to-frame registration through the mosaic tracker, with the prediction removed again.
#include "mapping/frame_registration.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "mosaic/raster_source.h"
#include "tracking/mosaic_tracker.h"
#include "tracking/motion_model.h"

namespace fleetloc::mapping {
namespace {

using geometry::Difference;
using geometry::Pose2;
using geometry::PoseWithCovariance;

// The reference frame seen as a mosaic lives in a local frame L with the image's axes (x right,
// y up) and its origin at the principal point, so level-0 mosaic pixels are the frame's pixels.
// By docs/formats.md (a up the image, b to its left) the reference's camera_ground is then the pose
// (0, 0, π/2) in L.
const Pose2 kReferenceInLocal{0.0, 0.0, M_PI / 2};

geometry::Geotransform LocalGeotransform(const geometry::CameraModel& camera) {
  return {-camera.cx_px * camera.resolution_m, camera.cy_px * camera.resolution_m,
          camera.resolution_m};
}

}  // namespace

tracking::TrackerOptions FramePairTrackerOptions() {
  tracking::TrackerOptions options;
  options.refine_passes = 1;
  options.max_search_radius_px = 64;
  options.polish_max_frame_pixels = 0;
  return options;
}

Status Validate(const RegistrationOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(tracking::Validate(o.tracker));
  if (o.min_inliers < 3) return InvalidInput("registration.min_inliers must be ≥ 3");
  if (!(o.min_prior_sigma_px > 0) || !(o.min_prior_sigma_rad > 0)) {
    return InvalidInput("registration.min_prior_sigma_px and _rad must be > 0");
  }
  if (!(o.min_template_sigma_px > 0)) {
    return InvalidInput("registration.min_template_sigma_px must be > 0");
  }
  return Status::Ok();
}

Result<PoseWithCovariance> RemovePrior(const PoseWithCovariance& prior,
                                       const PoseWithCovariance& posterior) {
  const Eigen::Matrix3d prior_information = prior.covariance.inverse();
  Eigen::Matrix3d information = posterior.covariance.inverse() - prior_information;
  information = 0.5 * (information + information.transpose()).eval();
  const Eigen::LLT<Eigen::Matrix3d> llt(information);
  if (llt.info() != Eigen::Success) {
    return NotFound("the matches carry no information beyond the prediction");
  }
  // posterior_info · x_post = prior_info · x_prior + info · x_meas (linearized at x_post).
  const Eigen::Vector3d pull =
      llt.solve(prior_information * Difference(posterior.pose, prior.pose));
  const Pose2 measured{posterior.pose.x + pull.x(), posterior.pose.y + pull.y(),
                       geometry::WrapAngle(posterior.pose.theta + pull.z())};
  return PoseWithCovariance{measured, llt.solve(Eigen::Matrix3d::Identity())};
}

FrameRegistrar::FrameRegistrar(const RegistrationOptions& options,
                               const geometry::CameraModel& camera)
    : options_(options), camera_(camera) {
  camera_.mount = Pose2{};
}

PoseWithCovariance FrameRegistrar::Widened(const PoseWithCovariance& predicted) const {
  const double min_sigma_m = options_.min_prior_sigma_px * camera_.resolution_m;
  const Eigen::Vector3d floor(min_sigma_m * min_sigma_m, min_sigma_m * min_sigma_m,
                              options_.min_prior_sigma_rad * options_.min_prior_sigma_rad);
  PoseWithCovariance widened = predicted;
  for (int i = 0; i < 3; ++i) {
    widened.covariance(i, i) = std::max(widened.covariance(i, i), floor[i]);
  }
  return widened;
}

Result<FrameRegistration> FrameRegistrar::Register(const cv::Mat& reference, const cv::Mat& target,
                                                   const PoseWithCovariance& predicted) const {
  mosaic::ImageRasterSource source(reference, LocalGeotransform(camera_));
  tracking::MosaicTracker tracker(options_.tracker, camera_, &source);
  const PoseWithCovariance prior =
      geometry::Compose({kReferenceInLocal, Eigen::Matrix3d::Zero()}, Widened(predicted));
  tracker.Reset(prior, Pose2{});
  const tracking::FrameResult result = tracker.Track(target, 0.0, Pose2{});
  if (result.state != tracking::LockState::kTracking || result.inliers < options_.min_inliers) {
    return NotFound("only " + std::to_string(result.inliers) + " of " +
                    std::to_string(result.templates) + " template matches agree (need " +
                    std::to_string(options_.min_inliers) + ")");
  }
  // The tracker's prior is Reset's pose advanced by a zero odometry increment (Predict).
  const PoseWithCovariance tracker_prior =
      tracking::Predict(prior, Pose2{}, 0.0, options_.tracker.odometry);
  Result<PoseWithCovariance> measured = RemovePrior(tracker_prior, result.base_in_map);
  if (!measured.ok()) return measured.status();
  const double n = result.inliers;
  const double sigma_px =
      std::max(options_.min_template_sigma_px, result.rms_residual_px * std::sqrt(n / (2 * n - 3)));
  measured->covariance *= std::pow(sigma_px / options_.tracker.measurement_sigma_px, 2);
  FrameRegistration registration;
  registration.relative =
      geometry::Compose({kReferenceInLocal.Inverse(), Eigen::Matrix3d::Zero()}, *measured);
  registration.inliers = result.inliers;
  registration.rms_residual_px = result.rms_residual_px;
  return registration;
}

}  // namespace fleetloc::mapping
