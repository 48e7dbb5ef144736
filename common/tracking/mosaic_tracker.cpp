// The tracker cycle: input transforms, lookup, preprocessing, overlap, the measurement (the
// templates, mosaic_tracker_templates.cpp, and the dense alignment), Kalman refinement with
// outlier rejection, output transforms.
#include "tracking/mosaic_tracker.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "timing/elapsed.h"
#include "tracking/motion_model.h"

namespace fleetloc::tracking {

using geometry::Pose2;
using geometry::PoseWithCovariance;
using timing::MsSince;

const char* DirectUseName(DirectUse use) {  // declared in frame_localizer.h
  switch (use) {
    case DirectUse::kNotRun:
      return "not_run";
    case DirectUse::kUsed:
      return "used";
    case DirectUse::kRefused:
      return "refused";
    case DirectUse::kDisagreed:
      return "disagreed";
  }
  return "not_run";
}

MosaicTracker::MosaicTracker(const TrackerOptions& options, const geometry::CameraModel& camera,
                             mosaic::RasterSource* mosaic)
    : options_(options),
      camera_(camera),
      mosaic_(mosaic),
      normalized_(mosaic, options.normalize_window_px,
                  static_cast<size_t>(options.normalized_cache_mb) << 20,
                  options.match_smoothing_sigma_px),
      matcher_(options, &normalized_),
      direct_(options.direct, camera, &normalized_),
      estimate_(camera.mount, options.odometry),
      polish_(PolishesEveryFrame(options, camera)),
      polish_dense_(static_cast<long long>(camera.width_px) * camera.height_px <=
                    options.polish_dense_max_frame_pixels) {}

void MosaicTracker::Reset(const PoseWithCovariance& base_in_map, const Pose2& odom) {
  estimate_.Reset(base_in_map, odom);
  coasting_frames_ = 0;
  state_ = LockState::kTracking;
  direct_first_ = false;
  template_failures_ = 0;
  weak_first_frames_left_ = 0;
  standard_template_misses_ = 0;
  polish_model_ = {};
  frames_since_model_ = 0;
}

int MosaicTracker::WarmUp(const PoseWithCovariance& base_in_map, int max_tiles) {
  const PoseWithCovariance camera = geometry::ComposeFixed(base_in_map, camera_.mount);
  const int radius = std::min(FrameSearchRadius(camera), options_.max_search_radius_px);
  const mosaic::MosaicLayout& layout = mosaic_->layout();
  const Eigen::Vector2d center = layout.geo.MapToPixel({camera.pose.x, camera.pose.y});
  const int reach = static_cast<int>(std::hypot(camera_.width_px, camera_.height_px) / 2) + radius;
  int normalized = 0;
  for (int level = 0; level <= CoarseLevels(radius) && normalized < max_tiles; ++level) {
    const cv::Rect box((static_cast<int>(center.x()) - reach) >> level,
                       (static_cast<int>(center.y()) - reach) >> level, (2 * reach) >> level,
                       (2 * reach) >> level);
    mosaic::TilesCovering(layout, level, box).ForEach([&](const mosaic::TileKey& key) {
      if (normalized < max_tiles && normalized_.Prepare(key)) ++normalized;
    });
  }
  return normalized;
}

FrameResult MosaicTracker::Coast(double t, const Pose2& odom) {
  FLEETLOC_CHECK(estimate_.initialized());
  const PoseWithCovariance& predicted = estimate_.Predict(t, odom);
  ++coasting_frames_;
  const bool lost = coasting_frames_ > options_.max_coasting_frames ||
                    SearchRadius(predicted, {camera_.cx_px, camera_.cy_px}) > MaxSearchRadius();
  return Finish(t, lost ? LockState::kLost : LockState::kCoasting);
}

// The dense alignment from `start`: its posterior when it validates.
std::optional<PoseWithCovariance> MosaicTracker::AlignDirect(const cv::Mat& frame,
                                                             const PoseWithCovariance& prior,
                                                             const Pose2& start, bool refine_only,
                                                             FrameResult* stats) const {
  const auto t_direct = std::chrono::steady_clock::now();
  const bool located_last = coasting_frames_ == 0 && state_ != LockState::kLost;
  const DirectAlignment dense = direct_.Align(frame, prior, start, located_last, refine_only);
  stats->direct_ms += MsSince(t_direct);
  stats->direct = dense.valid ? DirectUse::kUsed : DirectUse::kRefused;
  stats->direct_reason = dense.reason;
  stats->direct_correlation = dense.correlation;
  stats->direct_coarse_correlation = dense.coarse_correlation;
  stats->direct_peak_ratio = dense.peak_ratio;
  stats->direct_peak_z = dense.peak_z;
  stats->direct_searches = dense.searches;
  stats->direct_iterations = dense.iterations;
  stats->direct_sigma_px = dense.sigma_px;
  stats->direct_chi2 = dense.prior_chi2;
  stats->direct_needs_polish = dense.valid && dense.needs_polish;
  if (!dense.valid) return std::nullopt;
  return dense.posterior;
}

FrameResult MosaicTracker::Track(const cv::Mat& frame, double t, const Pose2& odom,
                                 double extrapolated_s) {
  FLEETLOC_CHECK(estimate_.initialized());
  FLEETLOC_CHECK(frame.type() == CV_8UC1);
  // Step 1: tracking-error compensation — the odometry increment is added to the tracker's own
  // last estimate (never the external absolute pose), with covariance growth.
  const PoseWithCovariance prior = estimate_.Predict(t, odom, extrapolated_s);
  const int full_radius = FrameSearchRadius(prior);
  // Beyond the largest search the prediction may still be good (3 sigma is conservative):
  // search the largest window anyway, and call the vehicle lost only if that fails.
  const bool beyond_search = full_radius > MaxSearchRadius();
  FrameResult result;
  result.search_radius_px = std::min(full_radius, options_.max_search_radius_px);
  // Steps 2–4: the frame measured against the mosaic around the prediction.
  bool templates_locked = false;
  FramePyramid pyramid(frame);
  std::optional<PoseWithCovariance> posterior =
      Measure(&pyramid, prior, result.search_radius_px, &templates_locked, &result);
  // The fit taken over every pixel at full resolution (docs/architecture.md, step 7c).
  if (posterior && ToPolish(templates_locked, result)) {
    posterior = Polished(&pyramid, prior, *posterior, &result);
  }
  if (posterior && result.direct_needs_polish && !result.polished) {
    result.direct = DirectUse::kRefused;
    result.direct_reason = "weak fit the polish did not confirm";
    posterior.reset();
  }
  // Step 5: the estimate corrected, and the lock state.
  const LockState state = UpdateLock(posterior, beyond_search);
  const FrameResult report = Finish(t, state);
  result.t = report.t;
  result.base_in_map = report.base_in_map;
  result.state = report.state;
  if (!posterior || !templates_locked) result.inliers = 0;
  return result;
}

// The templates and the dense alignment on the frame, from `prior`: the posterior to correct
// with, or nothing (coast). Where the templates failed on the last frame and the dense alignment
// did not (a weak floor), the dense alignment goes first; every retry_templates_frames frames the
// templates get another chance. `templates_locked`: the templates' fit was found.
std::optional<PoseWithCovariance> MosaicTracker::Measure(FramePyramid* pyramid,
                                                         const PoseWithCovariance& prior,
                                                         int radius_px, bool* templates_locked,
                                                         FrameResult* stats) {
  const cv::Mat frame = pyramid->frame();
  const bool direct_first =
      direct_first_ && frames_since_templates_ < options_.retry_templates_frames;
  if (direct_first) {
    std::optional<PoseWithCovariance> dense = AlignDirect(frame, prior, prior.pose, false, stats);
    if (dense) {
      ++frames_since_templates_;
      return dense;
    }
  }
  frames_since_templates_ = 0;
  const bool weak_first = weak_first_frames_left_ > 0;
  const std::optional<PoseWithCovariance> template_fit =
      MatchTemplates(pyramid, prior, radius_px, weak_first, stats);
  *templates_locked = template_fit.has_value();
  ChooseTemplateSizeAfter(template_fit ? stats->template_size_px : 0, weak_first);
  std::optional<PoseWithCovariance> posterior =
      Decide(frame, prior, template_fit, direct_first, stats);
  template_failures_ = *templates_locked ? 0 : template_failures_ + 1;
  direct_first_ = template_failures_ >= options_.direct_first_after_failures &&
                  stats->direct == DirectUse::kUsed;
  return posterior;
}

// The estimate corrected with `posterior` (tracking, or relocalized after lost), or the frame
// coasts (lost when beyond the largest search or after max_coasting_frames).
LockState MosaicTracker::UpdateLock(const std::optional<PoseWithCovariance>& posterior,
                                    bool beyond_search) {
  if (posterior) {
    estimate_.Correct(*posterior);
    coasting_frames_ = 0;
    return state_ == LockState::kLost ? LockState::kRelocalized : LockState::kTracking;
  }
  ++coasting_frames_;
  if (beyond_search || coasting_frames_ > options_.max_coasting_frames) return LockState::kLost;
  return LockState::kCoasting;
}

// The templates' fit and the dense alignment combined: the posterior to take, or nothing (coast).
// `direct_tried`: the dense alignment already ran from the prediction and was refused.
std::optional<PoseWithCovariance> MosaicTracker::Decide(
    const cv::Mat& frame, const PoseWithCovariance& prior,
    const std::optional<PoseWithCovariance>& templates, bool direct_tried,
    FrameResult* stats) const {
  if (templates && !options_.direct_refine) return templates;
  if (!templates && direct_tried) return std::nullopt;
  std::optional<PoseWithCovariance> dense = AlignDirect(
      frame, prior, templates ? templates->pose : prior.pose, templates.has_value(), stats);
  if (!dense) return templates;
  if (!templates) return dense;
  // Both fits: they must agree, or the frame coasts.
  if (!Agree(*dense, *templates)) {
    stats->direct = DirectUse::kDisagreed;
    return std::nullopt;
  }
  return dense;
}

// Every located frame is polished on small cameras (polish_max_frame_pixels) and on large ones
// (polish_min_frame_pixels).
bool MosaicTracker::PolishesEveryFrame(const TrackerOptions& options,
                                       const geometry::CameraModel& camera) {
  const long long pixels = static_cast<long long>(camera.width_px) * camera.height_px;
  return pixels <= options.polish_max_frame_pixels ||
         (options.polish_min_frame_pixels > 0 && pixels >= options.polish_min_frame_pixels);
}

// Whether to polish a located frame: on a camera that polishes every frame, a template fit, and a
// dense fit when the polish works at a finer level than the dense alignment ended at (320×240:
// level 0 against 1; 1280×1024: 1 against 2) or when it is weak. At 640×480 both work at level 1:
// polishing every dense fit there took painted pavement 001 under `dusty` (34 of 60 frames
// dense-located) from 1.9 to 3.2 ms a frame against its 2 ms budget. Elsewhere the weak dense
// fits alone.
bool MosaicTracker::ToPolish(bool templates_locked, const FrameResult& stats) const {
  if (templates_locked) return polish_;
  if (polish_ && direct_.PolishLevel() < direct_.FinestLevel()) return true;
  return WeakDenseFitToPolish(stats);
}

// A frame the dense alignment located with a weak correlation at its finest level (level 1 or
// coarser): there the fit is least precise, and the polish over every full-resolution pixel gains
// most (docs/benchmarks.md, "The dense fits polished at 640×480"); or one valid only once
// polished. On larger cameras neither is polished, and the second is refused.
bool MosaicTracker::WeakDenseFitToPolish(const FrameResult& stats) const {
  return polish_dense_ && stats.direct == DirectUse::kUsed &&
         (stats.direct_needs_polish ||
          stats.direct_correlation < options_.polish_dense_below_correlation);
}

// Two fits of the same frame agree when their difference is within max_disagreement_chi2 of
// their combined covariance.
bool MosaicTracker::Agree(const PoseWithCovariance& a, const PoseWithCovariance& b) const {
  const Eigen::Vector3d d(a.pose.x - b.pose.x, a.pose.y - b.pose.y,
                          geometry::WrapAngle(a.pose.theta - b.pose.theta));
  const Eigen::Matrix3d both = a.covariance + b.covariance;
  return d.dot(both.ldlt().solve(d)) <= options_.max_disagreement_chi2;
}

// The located frame's fit polished over every pixel at full resolution, when the polish
// validates (within max_polish_shift_px of the fit, correlating); else the fit as it was. No χ²
// agreement with the fit's covariance: that covariance is the level's it ended at, and it leaves
// out that level's own model error. Measured at 320×240 on painted pavement 001 under `all`: every
// polish refused by that test (χ² 21–30) was right (0.06–0.10 px from the truth) where the fit was
// 0.41–0.79 px off (docs/benchmarks.md, "The polish's gates", session 35).
PoseWithCovariance MosaicTracker::Polished(FramePyramid* pyramid, const PoseWithCovariance& prior,
                                           const PoseWithCovariance& fit, FrameResult* stats) {
  const auto t_polish = std::chrono::steady_clock::now();
  const bool estimate_model = polish_model_.view_blur_px < 0 ||
                              ++frames_since_model_ >= options_.direct.view_blur_every_frames;
  // A camera that polishes every frame does so at direct.polish_max_level_pixels' level; one that
  // polishes only its weak dense fits, at polish_dense_max_level_pixels'.
  const int level =
      polish_ ? direct_.PolishLevel() : direct_.PolishLevel(options_.polish_dense_max_level_pixels);
  const DirectAlignment polished = direct_.Polish(pyramid->Level(level), prior, fit.pose,
                                                  estimate_model ? PolishModel{} : polish_model_,
                                                  stats->direct_needs_polish, level);
  stats->polish_ms += MsSince(t_polish);
  stats->view_blur_px = polished.view_blur_px;
  if (!polished.valid) return fit;
  if (estimate_model) {
    polish_model_ = {polished.view_blur_px, polished.noise, polished.window_px,
                     polished.unsmoothed};
    frames_since_model_ = 0;
  }
  stats->polished = true;
  return polished.posterior;
}

void MosaicTracker::DropTiles(const std::vector<mosaic::TileKey>& changed) {
  for (const mosaic::TileKey& key : changed) {
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc)
        normalized_.cache().Erase({key.level, key.col + dc, key.row + dr});
    }
  }
}

// Step 8: output transforms — remove the mount offset, report base_link at the frame time.
FrameResult MosaicTracker::Finish(double t, LockState state) {
  state_ = state;
  return estimate_.Report(t, state);
}

}  // namespace fleetloc::tracking
