// The dense aligner's final refinement at full resolution: every pixel of the frame against the
// mosaic view blurred to the frame's own blur (see DirectAligner::Polish in direct_aligner.h).
#include <algorithm>
#include <cmath>
#include <optional>

#include "geometry/convex_polygon.h"
#include "imaging/fast_patch.h"
#include "tracking/dense_linearization.h"
#include "tracking/direct_aligner.h"
#include "tracking/direct_aligner_parts.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/frame_pyramid.h"
#include "tracking/noise_precision.h"
#include "tracking/predicted_view.h"
#include "tracking/view_blur.h"

namespace fleetloc::tracking {

using direct_detail::GrownBy;
using geometry::Difference;
using geometry::Pose2;
using geometry::PoseWithCovariance;

namespace {

// `image` (pixels of `level`) normalized over `window` level pixels; `as_tiles` (level 0 only):
// as the mosaic's tiles are (its window and the matching's smoothing).
cv::Mat NormalizedAt(const NormalizedMosaic& mosaic, const cv::Mat& image, int window,
                     bool as_tiles, cv::Mat* local_variance = nullptr) {
  if (as_tiles) return mosaic.Normalize(image, 0, local_variance);
  return imaging::NormalizePatch(image, window, NormalizedMosaic::kSpreadEpsilon, local_variance);
}

// The normalized mosaic view of `rect` (pixels of `level`) from `pose`, normalized over `window`.
// Above level 0 it is the frame's own steps: the mosaic averaged over each pixel's 2^level square
// of level-0 pixels (RenderAreaAveragedView), then normalized at `level`. The mosaic's own coarser
// levels were averaged on the mosaic's pixel grid and subsampled: when the frame's grid runs
// parallel to it (a vehicle driving along the mosaic's axes), their aliasing differs from the
// frame's by an amount that depends on the sub-pixel phase between the grids, and the fit is pulled
// towards the mosaic's pixels (0.08 px at 1280×1024 measured, against 0.002 at other headings).
// Normalized at level 0 before averaging, the view's local contrast differed from the frame's
// (clean worn asphalt g8 at 1280×1024: 0.0035 px RMS, 0.0007 by the frame's steps). Until session
// 45 the view was rendered at level 0 and averaged down (4^level times the samples: a fifth of a
// 640×480 frame's time on concrete under `all`); the average over a square aligned with the mosaic
// is the same to float rounding at the headings where the grids run parallel, and a turned square
// of the same centre and size elsewhere (docs/benchmarks.md, session 45). `as_tiles` (level 0
// only): from the mosaic's normalized tiles instead.
cv::Mat PolishView(NormalizedMosaic* mosaic, const geometry::CameraModel& camera,
                   const cv::Rect& rect, const Pose2& pose, int level, int window, bool as_tiles) {
  const FrameMosaicWarp warp = FrameMosaicWarp::For(pose, camera, mosaic->layout().geo);
  if (as_tiles) return RenderNormalizedView(mosaic, rect, warp, 0);
  const int n = window / 2 + 1;
  const cv::Mat view = RenderAreaAveragedView(mosaic->source(), GrownBy(rect, n), warp, level);
  return NormalizedAt(*mosaic, view, window, false)(cv::Rect(n, n, rect.width, rect.height));
}

// Whether to take `alternative` over `usual`: valid, and its comparison sigma below `max_ratio` of
// the usual fit's (or the usual fit not valid).
bool MorePrecise(const DirectAlignment& alternative, const DirectAlignment& usual,
                 double max_ratio) {
  return alternative.valid &&
         (!usual.valid || alternative.comparison_sigma_px < max_ratio * usual.comparison_sigma_px);
}

// `frame` (the camera's, or already its pyramid level `level`) at pyramid level `level`.
cv::Mat AtLevel(const cv::Mat& frame, const geometry::CameraModel& camera, int level) {
  cv::Mat at = frame;
  if (frame.cols == camera.width_px && frame.rows == camera.height_px) {
    at = FramePyramid(frame).Level(level);
  }
  CV_Assert(at.cols == camera.width_px >> level && at.rows == camera.height_px >> level);
  return at;
}

constexpr float kEpsilon = NormalizedMosaic::kSpreadEpsilon;

// The pixels' precision under model.noise when given; an empty map (all alike) when the noise
// model is off; none yet when it is to be fitted.
std::optional<cv::Mat> GivenPrecision(bool noise_model, const PolishModel& model,
                                      const cv::Mat& local_variance) {
  if (!noise_model) return cv::Mat();
  if (!model.noise) return std::nullopt;
  return ResidualPrecision(*model.noise, local_variance, kEpsilon);
}

int SpanPixels(const std::vector<cv::Range>& spans) {
  int pixels = 0;
  for (const cv::Range& span : spans) pixels += std::max(0, span.end - span.start);
  return pixels;
}

}  // namespace

// Per row of `inner` (pixels of `level`), the columns (relative to inner.x) whose pixel and its
// gradient neighbours fall inside the mosaic, with a pixel to spare, when the camera is at `pose`.
std::vector<cv::Range> DirectAligner::SpansInMosaic(const Pose2& pose, const cv::Rect& inner,
                                                    int level) const {
  const mosaic::MosaicLayout& layout = mosaic_->layout();
  constexpr double kSpare = 3.0;
  const double scale = 1.0 / (1 << level);
  const geometry::ConvexPolygon mosaic_in_frame =
      MosaicInFrame(FrameMosaicWarp::For(pose, camera_, layout.geo).AtLevel(level),
                    layout.width_px * scale, layout.height_px * scale, kSpare);
  std::vector<cv::Range> spans(inner.height);
  for (int y = 0; y < inner.height; ++y) {
    const auto [lo, hi] = geometry::SpanAtY(mosaic_in_frame, inner.y + y + 0.5);
    spans[y].start = lo > hi ? 0 : std::max(0, static_cast<int>(std::ceil(lo - 0.5)) - inner.x);
    spans[y].end =
        lo > hi ? 0 : std::min(inner.width, static_cast<int>(std::floor(hi - 0.5)) + 1 - inner.x);
  }
  return spans;
}

int DirectAligner::PolishLevel(int max_level_pixels) const {
  const long long pixels = static_cast<long long>(camera_.width_px) * camera_.height_px;
  int level = 0;
  while (max_level_pixels > 0 && level + 1 < levels_ && level < options_.polish_max_level &&
         (pixels >> (2 * level)) > max_level_pixels) {
    ++level;
  }
  return level;
}

// Every pixel of the frame at the polish level, from a pose already within a fraction of a pixel
// (see DirectAligner::Polish). Above level 0: over the window `model` gives, or over each candidate
// window, taking the wide window's fit when valid and more precise by
// polish_wide_window_max_sigma_ratio. At level 0: normalized as `model` gives, or both ways, taking
// the fit without the matching's smoothing when more precise by polish_unsmoothed_max_sigma_ratio.
DirectAlignment DirectAligner::Polish(const cv::Mat& frame, const PoseWithCovariance& prior,
                                      const Pose2& start, const PolishModel& model, bool confirming,
                                      int level) const {
  if (level < 0) level = PolishLevel();
  const int local = mosaic_->WindowAt(0), wide = options_.polish_wide_window_px;
  const auto over = [&](int window_px, bool unsmoothed) {
    return PolishOverWindow(frame, prior, start, model, confirming, level, {window_px, unsmoothed});
  };
  if (level == 0) {
    const double ratio = options_.polish_unsmoothed_max_sigma_ratio;
    if (model.unsmoothed || ratio <= 0) return over(local, model.unsmoothed.value_or(false));
    DirectAlignment smoothed = over(local, false), unsmoothed = over(local, true);
    return MorePrecise(unsmoothed, smoothed, ratio) ? unsmoothed : smoothed;
  }
  if (model.window_px >= 0) return over(model.window_px, false);
  if (wide <= local) return over(local, false);
  DirectAlignment over_local = over(local, false), over_wide = over(wide, false);
  return MorePrecise(over_wide, over_local, options_.polish_wide_window_max_sigma_ratio)
             ? over_wide
             : over_local;
}

// The polish with the frame and the view normalized as `normalization` says: over its window
// (level-0 px; the mosaic's at level 0), and at level 0 with the matching's smoothing (the view
// from the mosaic's normalized tiles) unless `unsmoothed`.
DirectAlignment DirectAligner::PolishOverWindow(const cv::Mat& frame_in,
                                                const PoseWithCovariance& prior, const Pose2& start,
                                                const PolishModel& model, bool confirming,
                                                int level,
                                                PolishNormalization normalization) const {
  DirectAlignment out;
  out.window_px = normalization.window_px;
  out.unsmoothed = level == 0 && normalization.unsmoothed;
  const bool as_tiles = level == 0 && !normalization.unsmoothed;
  const cv::Mat frame = AtLevel(frame_in, camera_, level);
  const int window = NormalizedMosaic::WindowAt(normalization.window_px, level);
  const int b = as_tiles ? mosaic_->MarginAt(0) : window / 2 + 1;
  const cv::Rect inner(b, b, frame.cols - 2 * b, frame.rows - 2 * b);
  const std::vector<cv::Range> spans = SpansInMosaic(start, inner, level);
  if (SpanPixels(spans) < inner.area() / 4) {
    out.reason = "frame mostly outside the mosaic";
    return out;
  }
  cv::Mat local_variance;
  const cv::Mat normalized = NormalizedAt(*mosaic_, frame, window, as_tiles, &local_variance);
  const cv::Rect view_rect(inner.x - 1, inner.y - 1, inner.width + 2, inner.height + 2);
  const Eigen::Vector2d principal = Eigen::Vector2d(camera_.cx_px, camera_.cy_px) / (1 << level);
  // The view blurred to the frame's blur, estimated at the start (see tracking/view_blur.h).
  const auto view_at = [&](const Pose2& pose, int margin) {
    return PolishView(mosaic_, camera_, GrownBy(view_rect, margin), pose, level, window, as_tiles);
  };
  double blur = std::max(0.0, model.view_blur_px);
  if (model.view_blur_px < 0 && options_.max_view_blur_px > 0) {
    const int m = BlurMarginPx(options_.max_view_blur_px);
    blur = BestViewBlur(normalized, view_at(start, m), m, inner, spans, options_.max_view_blur_px,
                        options_.view_blur_step_px, options_.tukey_c);
  }
  out.view_blur_px = blur;
  const int m = BlurMarginPx(blur);
  // Each pixel's precision under the residual noise (see tracking/noise_precision.h), fitted at
  // the first pass's view unless given; an empty map: all alike.
  std::optional<cv::Mat> precision = GivenPrecision(options_.noise_model, model, local_variance);
  if (model.noise) out.noise = *model.noise;
  const auto linearize = [&](const Pose2& pose, double sigma, double gain) {
    const cv::Mat view = BlurredView(view_at(pose, m), blur, m);
    if (!precision) {
      out.noise = FitResidualNoise(normalized, view, inner, spans, local_variance, kEpsilon);
      precision = ResidualPrecision(out.noise, local_variance, kEpsilon);
    }
    Linearization lin = LinearizeWholeFrame(normalized, view, inner, spans, principal,
                                            options_.tukey_c, sigma, gain, *precision);
    InLevel0Pixels(level, &lin);
    return lin;
  };
  Linearization fit;
  const Pose2 pose =
      GaussNewton(linearize, level,
                  confirming ? options_.confirm_polish_iterations : options_.polish_iterations,
                  prior, start, options_.converged_px, &out.iterations, &fit, options_.fit_contrast,
                  options_.polish_single_pass_px);
  FinishPolish(fit, prior, start, pose, &out);
  return out;
}

// A polish's result from its final linearization `fit` at `pose`: the fit's figures, the
// posterior, and whether it is taken.
void DirectAligner::FinishPolish(const Linearization& fit, const PoseWithCovariance& prior,
                                 const Pose2& start, const Pose2& pose,
                                 DirectAlignment* out) const {
  out->points = fit.points;
  out->correlation = out->coarse_correlation = fit.correlation;
  out->inlier_fraction = fit.inlier_fraction;
  Combine(fit, prior, pose, out);
  out->reason = PolishRefusal(*out, fit, pose, prior, start);
  out->valid = out->reason[0] == '\0';
}

// Why a polish from `start` that ended at `pose` (`fit`: its final linearization, `polished`: its
// combination with the prior) is not taken, or "".
const char* DirectAligner::PolishRefusal(const DirectAlignment& polished, const Linearization& fit,
                                         const Pose2& pose, const PoseWithCovariance& prior,
                                         const Pose2& start) const {
  if (polished.reason[0] != '\0') return polished.reason;
  const double moved_px =
      Difference(polished.posterior.pose, start).head<2>().norm() / camera_.resolution_m;
  if (moved_px > options_.max_polish_shift_px) return "polish moved too far";
  if (StepPx(MapStep(fit, pose, prior), 0) > options_.max_polish_next_step_px) {
    return "polish has not converged";
  }
  if (fit.correlation < options_.min_polish_correlation) return "polish does not correlate";
  if (polished.sigma_px > options_.max_sigma_px) return "weakly constrained";
  return "";
}

}  // namespace fleetloc::tracking
