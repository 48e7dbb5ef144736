// Mosaic resampling, normalization and NCC for one template site.
#include "tracking/template_matcher.h"

#include "imaging/normalize.h"
#include "tracking/predicted_view.h"

namespace fleetloc::tracking {

TemplateMatcher::TemplateMatcher(const TrackerOptions& options, mosaic::RasterSource* mosaic)
    : options_(options), mosaic_(mosaic) {}

bool TemplateMatcher::PassesGates(const imaging::Match& m) const {
  return m.found && m.peak >= options_.min_peak_correlation &&
         m.second_peak < options_.max_ambiguity_ratio * m.peak &&
         m.curvature >= options_.min_peak_curvature;
}

std::optional<SiteMatch> TemplateMatcher::Match(const cv::Mat& frame,
                                                const Eigen::Vector2d& center_px, int radius_px,
                                                const FrameMosaicWarp& warp) const {
  const int t = options_.template_size_px, m = margin_px();
  const cv::Point top_left(static_cast<int>(center_px.x()) - t / 2,
                           static_cast<int>(center_px.y()) - t / 2);
  const cv::Rect template_rect(top_left.x - m, top_left.y - m, t + 2 * m, t + 2 * m);
  if ((template_rect & cv::Rect(0, 0, frame.cols, frame.rows)) != template_rect) return {};
  // Normalize with a margin, then crop, so template and view pixels see whole neighbourhoods.
  const int w = options_.normalize_window_px;
  const cv::Mat templ = imaging::LocalNormalize(frame(template_rect), w)(cv::Rect(m, m, t, t));
  const int view_size = t + 2 * radius_px + 2 * m;
  const cv::Mat view = RenderPredictedView(
      mosaic_, {top_left - cv::Point(radius_px + m, radius_px + m), cv::Size(view_size, view_size)},
      warp);
  const cv::Mat view_n = imaging::LocalNormalize(view, w)(
      cv::Rect(m, m, view_size - 2 * m, view_size - 2 * m));
  const imaging::Match match = imaging::MatchTemplate(view_n, templ.clone());
  if (!PassesGates(match)) return {};
  return SiteMatch{match.offset_px - Eigen::Vector2d(radius_px, radius_px), match};
}

}  // namespace fleetloc::tracking
