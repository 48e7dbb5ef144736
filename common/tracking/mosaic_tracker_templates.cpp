// The tracker cycle's template steps (see mosaic_tracker.h): search radii from the prediction,
// template selection where the frame has texture, coarse-to-fine matching against the normalized
// mosaic, and the Kalman update with outlier rejection over the matches.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "imaging/fast_patch.h"
#include "timing/elapsed.h"
#include "tracking/feature_selection.h"
#include "tracking/mosaic_tracker.h"
#include "tracking/motion_model.h"

namespace fleetloc::tracking {

using geometry::Pose2;
using geometry::PoseWithCovariance;
using timing::MsSince;

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
  std::vector<TemplateSite> candidates =
      CandidateSites(texture, 2 * half_step, bounds, min_texture);
  // Debris and marks, the strongest texture of an occluded frame, must not take every standard
  // pick (texture_cap_quantile); a weak floor's few strong sites are its best.
  if (template_size_px == options_.template_size_px) {
    CapTexture(options_.texture_cap_quantile, &candidates);
  }
  // A small camera's frame, polished, needs only enough standard templates to bring its fit within
  // the polish's reach (the 2 ms budget at 640×480). Large cameras keep them all (at 1280×1024 the
  // cap raised 9 cells' camera RMS by 3–20 %), and so do the weak-floor templates (a weak floor's
  // fit needs every one of them to lock: plain concrete b1 under `all` at 640×480 locked 14 of 60
  // frames with 10, 49 with 28).
  const long long pixels = static_cast<long long>(camera_.width_px) * camera_.height_px;
  const bool capped =
      pixels <= options_.polish_max_frame_pixels && template_size_px == options_.template_size_px;
  const int max_templates = capped
                                ? std::min(options_.max_templates, options_.polished_max_templates)
                                : options_.max_templates;
  return SelectSites(candidates, max_templates, options_.spread_sigma_px, template_size_px);
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
                                                  int fixed_radius_px, int level,
                                                  int retry_radius_px) const {
  const geometry::Geotransform& geo = mosaic_->layout().geo;
  const FrameMosaicWarp warp = FrameMosaicWarp::For(camera.pose, camera_, geo);
  const double sigma_m = options_.measurement_sigma_px * (1 << level) * camera_.resolution_m;
  Measured measured;
  for (const PreparedSite& prepared : sites) {
    const Eigen::Vector2d& center = prepared.site.center_px;
    const int full_radius = std::min(SearchRadius(camera, center), options_.max_search_radius_px);
    const int radius = fixed_radius_px > 0 ? fixed_radius_px : (full_radius >> level) + 1;
    std::optional<SiteMatch> match = matcher_.Match(prepared.templ, center, radius, warp, level);
    if (!match && retry_radius_px > radius) {  // e.g. the peak on a small window's border
      match = matcher_.Match(prepared.templ, center, retry_radius_px, warp, level);
    }
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
std::optional<PoseWithCovariance> MosaicTracker::MatchTemplates(FramePyramid* pyramid,
                                                                const PoseWithCovariance& prior,
                                                                int frame_radius, bool weak_first,
                                                                FrameResult* stats) const {
  std::vector<TemplateScale> scales{{options_.template_size_px, options_.coarse_template_size_px}};
  if (options_.weak_template_size_px > 0) {
    const TemplateScale weak{options_.weak_template_size_px, options_.weak_template_size_px};
    scales.insert(weak_first ? scales.begin() : scales.end(), weak);
  }
  // Texture on the half-resolution frame, at the candidate grid only; once for every size.
  const auto t_texture = std::chrono::steady_clock::now();
  const cv::Mat texture = imaging::TextureScoreGrid(
      pyramid->Level(1), std::max(1, options_.candidate_step_px / 2), options_.texture_window_px);
  stats->select_ms += MsSince(t_texture);
  for (const TemplateScale& scale : scales) {
    std::optional<PoseWithCovariance> fit =
        MatchTemplatesAt(pyramid, texture, prior, frame_radius, scale, stats);
    if (fit) {
      stats->template_size_px = scale.size_px;
      return fit;
    }
  }
  return std::nullopt;
}

// One template size: selection, coarse-to-fine matching and the Kalman update.
std::optional<PoseWithCovariance> MosaicTracker::MatchTemplatesAt(
    FramePyramid* pyramid, const cv::Mat& texture, const PoseWithCovariance& prior,
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
      const Measured coarse =
          MatchSites(Prepare(pyramid->Level(level), coarse_sites, scale.coarse_size_px, level),
                     center, first ? 0 : options_.refine_search_radius_px, level);
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
  if (!coarse_failed) fine_sites = Prepare(pyramid->frame(), sites, scale.size_px, 0);
  Measured measured = MatchSites(fine_sites, center, fine_radius, 0);
  stats->templates = std::max(stats->templates, static_cast<int>(measured.matches.size()));
  PoseUpdate update = Update(prior, measured, 0);
  // Further passes: resample the mosaic at the refined pose and re-match the inliers in a small
  // window (±refine_pass_radius_px), so the sub-pixel fit works near zero shift where its bias
  // vanishes. Not when the fit will be polished: the polish ends at the same pose with or without
  // them (camera RMS within 0.0002 px on the stress cells) and they cost 0.3 ms.
  const int refine_passes = polish_ ? 0 : options_.refine_passes;
  for (int pass = 0; pass < refine_passes && update.inliers >= options_.min_inliers; ++pass) {
    measured = MatchSites(Inliers(measured, update), update.posterior,
                          options_.refine_pass_radius_px, 0, options_.refine_search_radius_px);
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

// The next frame's first template size. The standard size goes first again on the next frame after
// it failed once: on a textured floor an occluder or a prediction far off its sigma fails it for a
// frame, and the weak-floor templates cost twice as much (painted pavement 001 under `marks` at
// 640×480: 1.9 against 2.8 ms a frame when they went first for ten frames after every failure).
// After 2, 3, 4… failures in a row (a weak floor), the weak-floor size goes first for 1, 3, 7…
// frames, at most retry_templates_frames, before the standard size is tried again.
// `locked_size_px`: the size that locked (0: none); `weak_went_first`: this frame tried the
// weak-floor size first.
void MosaicTracker::ChooseTemplateSizeAfter(int locked_size_px, bool weak_went_first) {
  const bool weak_locked = locked_size_px != 0 && locked_size_px != options_.template_size_px;
  const bool standard_tried = !(weak_went_first && weak_locked);
  if (weak_went_first) --weak_first_frames_left_;
  if (!standard_tried) return;
  standard_template_misses_ =
      locked_size_px == options_.template_size_px ? 0 : standard_template_misses_ + 1;
  if (weak_locked && standard_template_misses_ >= 2) {
    const int backoff = (1 << std::min(standard_template_misses_ - 1, 16)) - 1;
    weak_first_frames_left_ = std::min(backoff, options_.retry_templates_frames);
  }
}

}  // namespace fleetloc::tracking
