// The shared peer cycle: fleetloc's prediction, the predicted view, registration, the pose from
// five registered frame points through fleetloc's Kalman update, and the lock states.
#include "peers/peer_localizer.h"

#include <array>
#include <cmath>

#include "tracking/motion_model.h"
#include "tracking/predicted_view.h"

namespace fleetloc::peers {
namespace {

using geometry::Pose2;
using geometry::PoseWithCovariance;
using tracking::FrameResult;
using tracking::LockState;

// Where the pose-solve points sit, as fractions of the frame: four near the corners for a long
// heading lever, and the centre.
constexpr std::array<std::array<double, 2>, 5> kSampleFractions{
    {{0.1, 0.1}, {0.9, 0.1}, {0.1, 0.9}, {0.9, 0.9}, {0.5, 0.5}}};

bool AllFinite(const cv::Matx23d& m) {
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(m.val[i])) return false;
  }
  return true;
}

}  // namespace

PeerLocalizer::PeerLocalizer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                             int view_margin_px, const PeerOptions& options)
    : camera_(camera),
      mosaic_(mosaic),
      view_margin_px_(view_margin_px),
      options_(options),
      estimate_(camera.mount, options.odometry) {
  FLEETLOC_CHECK(mosaic_ != nullptr);
  FLEETLOC_CHECK(view_margin_px_ >= 0);
}

void PeerLocalizer::Reset(const PoseWithCovariance& base_in_map, const Pose2& odom) {
  estimate_.Reset(base_in_map, odom);
  coasting_frames_ = 0;
  state_ = LockState::kTracking;
}

std::optional<Registration> PeerLocalizer::TryRegister(const cv::Mat& frame, const cv::Mat& view) {
  try {
    return Register(frame, view);
  } catch (const cv::Exception&) {  // e.g. ECC non-convergence, degenerate RANSAC input
    return std::nullopt;
  }
}

// Rejects non-finite transforms, reflections, absurd scale or rotation, and registrations that
// put the frame's centre outside the view.
bool PeerLocalizer::Plausible(const Registration& registration, const cv::Size& view_size) const {
  const cv::Matx23d& m = registration.frame_to_view;
  if (!AllFinite(m)) return false;
  const double det = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  if (det <= 0.0) return false;
  const double rotation_rad = std::atan2(m(1, 0) - m(0, 1), m(0, 0) + m(1, 1));
  if (std::abs(std::sqrt(det) - 1.0) > options_.max_scale_error ||
      std::abs(rotation_rad) > options_.max_rotation_rad) {
    return false;
  }
  const cv::Vec2d centre = m * cv::Vec3d(camera_.width_px / 2.0, camera_.height_px / 2.0, 1.0);
  return centre[0] >= 0 && centre[1] >= 0 && centre[0] < view_size.width &&
         centre[1] < view_size.height;
}

// Frame point → (registration) view index → frame point the view shows under the prediction →
// (warp) mosaic pixel → map; the camera pose is then fleetloc's Kalman update over these.
tracking::PoseUpdate PeerLocalizer::SolvePose(const PoseWithCovariance& prior,
                                              const Registration& registration,
                                              const cv::Point& view_origin,
                                              const tracking::FrameMosaicWarp& warp) const {
  const geometry::Geotransform& geo = mosaic_->layout().geo;
  const double sigma_m = options_.measurement_sigma_px * camera_.resolution_m;
  std::vector<tracking::Correspondence> points;
  for (const auto& [fx, fy] : kSampleFractions) {
    const Eigen::Vector2d frame_px(fx * camera_.width_px, fy * camera_.height_px);
    const cv::Vec2d view_index =
        registration.frame_to_view * cv::Vec3d(frame_px.x() - 0.5, frame_px.y() - 0.5, 1.0);
    const Eigen::Vector2d seen_px(view_origin.x + view_index[0] + 0.5,
                                  view_origin.y + view_index[1] + 0.5);
    points.push_back({camera_.PixelToGround(frame_px), geo.PixelToMap(warp(seen_px)), sigma_m});
  }
  // The points come from one transform: nothing to reject.
  tracking::OutlierOptions keep_all;
  keep_all.ratio = 1e9;
  keep_all.min_residual_m = 1e9;
  keep_all.min_inliers = static_cast<int>(points.size());
  return tracking::KalmanPoseUpdate(prior, points, keep_all);
}

FrameResult PeerLocalizer::Coast(double t, const Pose2& odom) {
  FLEETLOC_CHECK(estimate_.initialized());
  estimate_.Predict(t, odom);
  ++coasting_frames_;
  return Finish(
      t, coasting_frames_ > options_.max_coasting_frames ? LockState::kLost : LockState::kCoasting);
}

FrameResult PeerLocalizer::Track(const cv::Mat& frame, double t, const Pose2& odom) {
  FLEETLOC_CHECK(estimate_.initialized());
  FLEETLOC_CHECK(frame.type() == CV_8UC1 && frame.cols == camera_.width_px &&
                 frame.rows == camera_.height_px);
  // Exactly fleetloc's step 1 (the shared InternalEstimate): odometry increment added to the
  // peer's own last estimate, with fleetloc's covariance growth.
  const PoseWithCovariance prior = estimate_.Predict(t, odom);
  const tracking::FrameMosaicWarp warp =
      tracking::FrameMosaicWarp::For(prior.pose, camera_, mosaic_->layout().geo);
  const int m = view_margin_px_;
  const cv::Rect view_rect(-m, -m, frame.cols + 2 * m, frame.rows + 2 * m);
  const cv::Mat view = tracking::RenderPredictedView(mosaic_, view_rect, warp);
  const std::optional<Registration> registration = TryRegister(frame, view);
  const bool ok = registration && Plausible(*registration, view.size());
  if (ok) {
    estimate_.Correct(SolvePose(prior, *registration, view_rect.tl(), warp).posterior);
    coasting_frames_ = 0;
  } else {
    ++coasting_frames_;
  }
  LockState state = LockState::kCoasting;
  if (ok) {
    state = state_ == LockState::kLost ? LockState::kRelocalized : LockState::kTracking;
  } else if (coasting_frames_ > options_.max_coasting_frames) {
    state = LockState::kLost;
  }
  FrameResult result = Finish(t, state);
  result.templates = registration ? registration->matches : 0;
  result.inliers = ok ? registration->inliers : 0;
  result.rms_residual_px = ok ? registration->rms_residual_px : 0.0;
  result.search_radius_px = m;
  return result;
}

// Output transforms as fleetloc's: base_link = camera ⊕ mount⁻¹ at the frame time.
FrameResult PeerLocalizer::Finish(double t, LockState state) {
  state_ = state;
  return estimate_.Report(t, state);
}

}  // namespace fleetloc::peers
