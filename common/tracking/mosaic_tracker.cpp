// The tracker cycle: input transforms, lookup, preprocessing, overlap, selection, matching,
// Kalman refinement with outlier rejection, output transforms.
#include "tracking/mosaic_tracker.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "imaging/fast_patch.h"
#include "tracking/feature_selection.h"
#include "tracking/motion_model.h"

namespace fleetloc::tracking {
namespace {

double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The frame pyramid up to `level` (each level half the last, area-averaged).
const cv::Mat& PyramidLevel(std::vector<cv::Mat>* pyramid, int level) {
  while (static_cast<int>(pyramid->size()) <= level) {
    const cv::Mat& last = pyramid->back();
    cv::Mat next;
    cv::resize(last, next, {last.cols / 2, last.rows / 2}, 0, 0, cv::INTER_AREA);
    pyramid->push_back(next);
  }
  return (*pyramid)[level];
}

}  // namespace

using geometry::Pose2;
using geometry::PoseWithCovariance;


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
      polish_(static_cast<long long>(camera.width_px) * camera.height_px <=
              options.polish_max_frame_pixels) {}

void MosaicTracker::Reset(const PoseWithCovariance& base_in_map, const Pose2& odom) {
  estimate_.Reset(base_in_map, odom);
  coasting_frames_ = 0;
  state_ = LockState::kTracking;
  direct_first_ = false;
  template_failures_ = 0;
  weak_templates_first_ = false;
  frames_on_weak_templates_ = 0;
  view_blur_px_ = -1.0;
  frames_since_blur_ = 0;
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

// Search half-size for a frame point: 3 sigma of the predicted position of that point.
int MosaicTracker::SearchRadius(const PoseWithCovariance& camera, const Eigen::Vector2d& px) const {
  const Eigen::Matrix<double, 2, 3> j =
      geometry::PointJacobian(camera.pose, camera_.PixelToGround(px));
  const Eigen::Matrix2d cov = j * camera.covariance * j.transpose();
  const double sigma_px =
      std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues().maxCoeff()) /
      camera_.resolution_m;
  const double r = std::ceil(options_.search_sigma_multiple * sigma_px) + 1.0;
  return static_cast<int>(std::clamp(r, double(options_.min_search_radius_px), 1e6));
}

// The widest prediction error a frame can still be found from: the template search's, or the dense
// alignment's coarse search (max_search_px at its coarsest level).
int MosaicTracker::MaxSearchRadius() const {
  return std::max(options_.max_search_radius_px,
                  options_.direct.max_search_px << (direct_.levels() - 1));
}

// Steps 3–5: texture score, overlap polygon, greedy selection.
std::vector<TemplateSite> MosaicTracker::ChooseSites(const cv::Mat& texture, const Pose2& camera,
                                                     int radius_px, int template_size_px) const {
  const mosaic::MosaicLayout& layout = mosaic_->layout();
  const geometry::ConvexPolygon mosaic_in_frame = MosaicInFrame(
      FrameMosaicWarp::For(camera, camera_, layout.geo), layout.width_px, layout.height_px);
  const int half_step = std::max(1, options_.candidate_step_px / 2);
  // A template must lie in the frame; its search window only in the mosaic (the window is cut
  // from the mosaic, not the frame), so sites near the frame's edges stay usable however wide the
  // search: on small frames and fast runs that is most of the frame.
  const double template_half = template_size_px / 2.0 + matcher_.margin_px();
  const std::vector<SiteBounds> bounds{
      {geometry::Rectangle(0, 0, camera_.width_px, camera_.height_px), template_half},
      {mosaic_in_frame, template_half + radius_px}};
  const double min_texture = RelativeTextureThreshold(
      texture, options_.texture_quantile, options_.relative_texture, options_.min_texture);
  const std::vector<TemplateSite> candidates =
      CandidateSites(texture, 2 * half_step, bounds, min_texture);
  return SelectSites(candidates, options_.max_templates, options_.spread_sigma_px,
                     template_size_px);
}

// Step 3 (frame side): normalized templates, cut once per frame and level.
std::vector<MosaicTracker::PreparedSite> MosaicTracker::Prepare(
    const cv::Mat& frame_at_level, const std::vector<TemplateSite>& sites, int size_px,
    int level) const {
  std::vector<PreparedSite> prepared;
  for (const TemplateSite& site : sites) {
    cv::Mat templ = matcher_.Template(frame_at_level, site.center_px, size_px, level);
    if (!templ.empty()) prepared.push_back({site, std::move(templ)});
  }
  return prepared;
}

// Step 6: each site matched within its own radius (or a fixed one), as map correspondences.
MosaicTracker::Measured MosaicTracker::MatchSites(const std::vector<PreparedSite>& sites,
                                                  const PoseWithCovariance& camera,
                                                  int fixed_radius_px, int level) const {
  const geometry::Geotransform& geo = mosaic_->layout().geo;
  const FrameMosaicWarp warp = FrameMosaicWarp::For(camera.pose, camera_, geo);
  const double sigma_m = options_.measurement_sigma_px * (1 << level) * camera_.resolution_m;
  Measured measured;
  for (const PreparedSite& prepared : sites) {
    const Eigen::Vector2d& center = prepared.site.center_px;
    const int full_radius = std::min(SearchRadius(camera, center), options_.max_search_radius_px);
    const int radius = fixed_radius_px > 0 ? fixed_radius_px : (full_radius >> level) + 1;
    const std::optional<SiteMatch> match =
        matcher_.Match(prepared.templ, center, radius, warp, level);
    if (!match) continue;
    const Eigen::Vector2d observed = geo.PixelToMap(warp(center + match->shift_px));
    measured.sites.push_back(prepared);
    measured.matches.push_back({camera_.PixelToGround(center), observed, sigma_m});
  }
  return measured;
}

PoseUpdate MosaicTracker::Update(const PoseWithCovariance& prior, const Measured& measured,
                                 int level) const {
  OutlierOptions outliers;
  outliers.ratio = options_.outlier_ratio;
  outliers.min_residual_m = options_.min_outlier_residual_px * (1 << level) * camera_.resolution_m;
  outliers.min_inliers = options_.min_inliers;
  return KalmanPoseUpdate(prior, measured.matches, outliers);
}

std::vector<MosaicTracker::PreparedSite> MosaicTracker::Inliers(const Measured& measured,
                                                                const PoseUpdate& update) {
  std::vector<PreparedSite> kept;
  for (size_t i = 0; i < measured.sites.size(); ++i) {
    if (update.inlier[i]) kept.push_back(measured.sites[i]);
  }
  return kept;
}

FrameResult MosaicTracker::Coast(double t, const Pose2& odom) {
  FLEETLOC_CHECK(estimate_.initialized());
  const PoseWithCovariance& predicted = estimate_.Predict(t, odom);
  ++coasting_frames_;
  const bool lost = coasting_frames_ > options_.max_coasting_frames ||
                    SearchRadius(predicted, {camera_.cx_px, camera_.cy_px}) > MaxSearchRadius();
  return Finish(t, lost ? LockState::kLost : LockState::kCoasting);
}

// The frame's search radius (level-0 px): the largest 3-sigma of the prediction at its corners.
int MosaicTracker::FrameSearchRadius(const PoseWithCovariance& prior) const {
  int radius = 0;
  for (const auto& corner : geometry::Rectangle(0, 0, camera_.width_px, camera_.height_px)) {
    radius = std::max(radius, SearchRadius(prior, corner));
  }
  return radius;
}

// Steps 3–7 with templates: the preferred template size first, the other when it fails (a floor
// too weak for the standard templates often locks with larger ones, far cheaper than the dense
// alignment). The fit when at least min_inliers templates were kept.
std::optional<PoseWithCovariance> MosaicTracker::MatchTemplates(const cv::Mat& frame,
                                                                const PoseWithCovariance& prior,
                                                                int frame_radius, bool weak_first,
                                                                FrameResult* stats) const {
  std::vector<TemplateScale> scales{{options_.template_size_px, options_.coarse_template_size_px}};
  if (options_.weak_template_size_px > 0) {
    const TemplateScale weak{options_.weak_template_size_px, options_.weak_template_size_px};
    scales.insert(weak_first ? scales.begin() : scales.end(), weak);
  }
  std::vector<cv::Mat> pyramid{frame};
  // Texture on the half-resolution frame, at the candidate grid only; once for every size.
  const auto t_texture = std::chrono::steady_clock::now();
  const cv::Mat texture = imaging::TextureScoreGrid(PyramidLevel(&pyramid, 1),
                                                    std::max(1, options_.candidate_step_px / 2),
                                                    options_.texture_window_px);
  stats->select_ms += MsSince(t_texture);
  for (const TemplateScale& scale : scales) {
    const std::optional<PoseWithCovariance> fit =
        MatchTemplatesAt(&pyramid, texture, prior, frame_radius, scale, stats);
    if (fit) {
      stats->template_size_px = scale.size_px;
      return fit;
    }
  }
  return std::nullopt;
}

// One template size: selection, coarse-to-fine matching and the Kalman update.
std::optional<PoseWithCovariance> MosaicTracker::MatchTemplatesAt(
    std::vector<cv::Mat>* pyramid, const cv::Mat& texture, const PoseWithCovariance& prior,
    int frame_radius, const TemplateScale& scale, FrameResult* stats) const {
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  const std::vector<TemplateSite> sites =
      ChooseSites(texture, prior.pose, frame_radius, scale.size_px);
  stats->select_ms += MsSince(t_start);
  const auto t_coarse = Clock::now();
  // Coarse to fine when the window is large: search the frame pyramid from the coarsest level
  // whose window is small, refine ±refine radius at each finer level; the full-resolution search
  // then only needs ±refine radius around a pose already good to a fraction of a pixel.
  PoseWithCovariance center = prior;
  int fine_radius = 0;  // 0: each site's own 3-sigma radius
  bool coarse_failed = false;
  const int coarse_levels = CoarseLevels(frame_radius);
  if (frame_radius > options_.coarse_above_radius_px && coarse_levels >= 1) {
    const std::vector<TemplateSite> coarse_sites(
        sites.begin(), sites.begin() + std::min<size_t>(sites.size(), options_.coarse_templates));
    for (int level = coarse_levels; level >= 1 && !coarse_failed; --level) {
      const bool first = level == coarse_levels;
      const Measured coarse = MatchSites(
          Prepare(PyramidLevel(pyramid, level), coarse_sites, scale.coarse_size_px, level), center,
          first ? 0 : options_.refine_search_radius_px, level);
      const PoseUpdate coarse_update = Update(prior, coarse, level);
      stats->templates = std::max(stats->templates, static_cast<int>(coarse.matches.size()));
      coarse_failed = coarse_update.inliers < options_.min_inliers;
      center = coarse_update.posterior;
    }
    fine_radius = options_.refine_search_radius_px;
  }
  stats->coarse_ms += MsSince(t_coarse);
  const auto t_fine = Clock::now();
  std::vector<PreparedSite> fine_sites;
  if (!coarse_failed) fine_sites = Prepare((*pyramid)[0], sites, scale.size_px, 0);
  Measured measured = MatchSites(fine_sites, center, fine_radius, 0);
  stats->templates = std::max(stats->templates, static_cast<int>(measured.matches.size()));
  PoseUpdate update = Update(prior, measured, 0);
  // Further passes: resample the mosaic at the refined pose and re-match the inliers in a small
  // window, so the sub-pixel fit works near zero shift where its bias vanishes. Not when the fit
  // will be polished: the polish ends at the same pose with or without them (camera RMS within
  // 0.0002 px on the stress cells) and they cost 0.3 ms.
  const int refine_passes = polish_ ? 0 : options_.refine_passes;
  for (int pass = 0; pass < refine_passes && update.inliers >= options_.min_inliers; ++pass) {
    measured = MatchSites(Inliers(measured, update), update.posterior,
                          options_.refine_search_radius_px, 0);
    update = Update(prior, measured, 0);
  }
  stats->fine_ms += MsSince(t_fine);
  stats->inliers = update.inliers;
  stats->rms_residual_px = update.rms_residual_m / camera_.resolution_m;
  if (update.inliers < options_.min_inliers) return std::nullopt;
  return update.posterior;
}

// The pyramid level the coarse template search starts at: the finest whose window is small
// enough (each level halves it), as a template at a finer level keeps more of a weak floor's
// texture; a small mosaic may have fewer levels.
int MosaicTracker::CoarseLevels(int frame_radius) const {
  const int max_levels = std::min(options_.coarse_levels, mosaic_->layout().levels - 1);
  int levels = std::min(1, max_levels);
  while (levels < max_levels && (frame_radius >> levels) > options_.coarse_search_radius_px) {
    ++levels;
  }
  return levels;
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
  std::optional<PoseWithCovariance> posterior =
      Measure(frame, prior, result.search_radius_px, &templates_locked, &result);
  if (posterior && polish_) posterior = Polished(frame, prior, *posterior, &result);
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
std::optional<PoseWithCovariance> MosaicTracker::Measure(const cv::Mat& frame,
                                                         const PoseWithCovariance& prior,
                                                         int radius_px, bool* templates_locked,
                                                         FrameResult* stats) {
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
  const std::optional<PoseWithCovariance> template_fit =
      MatchTemplates(frame, prior, radius_px, weak_templates_first_, stats);
  *templates_locked = template_fit.has_value();
  ChooseTemplateSizeAfter(template_fit ? stats->template_size_px : 0);
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
  const std::optional<PoseWithCovariance> dense = AlignDirect(
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

// Two fits of the same frame agree when their difference is within max_disagreement_chi2 of
// their combined covariance.
bool MosaicTracker::Agree(const PoseWithCovariance& a, const PoseWithCovariance& b) const {
  const Eigen::Vector3d d(a.pose.x - b.pose.x, a.pose.y - b.pose.y,
                          geometry::WrapAngle(a.pose.theta - b.pose.theta));
  const Eigen::Matrix3d both = a.covariance + b.covariance;
  return d.dot(both.ldlt().solve(d)) <= options_.max_disagreement_chi2;
}

// The located frame's fit polished over every pixel at full resolution, when the polish
// validates and agrees with it; else the fit as it was.
PoseWithCovariance MosaicTracker::Polished(const cv::Mat& frame, const PoseWithCovariance& prior,
                                           const PoseWithCovariance& fit,
                                           FrameResult* stats) {
  const auto t_polish = std::chrono::steady_clock::now();
  const bool estimate_blur = view_blur_px_ < 0 ||
                             ++frames_since_blur_ >= options_.direct.view_blur_every_frames;
  const DirectAlignment polished =
      direct_.Polish(frame, prior, fit.pose, estimate_blur ? -1.0 : view_blur_px_);
  stats->polish_ms += MsSince(t_polish);
  stats->view_blur_px = polished.view_blur_px;
  if (!polished.valid || !Agree(polished.posterior, fit)) return fit;
  if (estimate_blur) {
    view_blur_px_ = polished.view_blur_px;
    frames_since_blur_ = 0;
  }
  stats->polished = true;
  return polished.posterior;
}

// The next frame starts with the template size that locked this one; after retry_templates_frames
// frames on the weak-floor size the standard one is tried first again. `locked_size_px`: 0 when
// no size locked.
void MosaicTracker::ChooseTemplateSizeAfter(int locked_size_px) {
  if (locked_size_px == 0) return;
  const bool weak = locked_size_px != options_.template_size_px;
  frames_on_weak_templates_ = weak ? frames_on_weak_templates_ + 1 : 0;
  weak_templates_first_ = weak && frames_on_weak_templates_ < options_.retry_templates_frames;
  if (!weak_templates_first_) frames_on_weak_templates_ = 0;
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
