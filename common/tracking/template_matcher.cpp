// Normalized template extraction and NCC against the normalized mosaic view.
#include "tracking/template_matcher.h"

#include "imaging/fast_patch.h"
#include "tracking/predicted_view.h"

namespace fleetloc::tracking {

TemplateMatcher::TemplateMatcher(const TrackerOptions& options, NormalizedMosaic* mosaic)
    : options_(options), mosaic_(mosaic) {}

bool TemplateMatcher::PassesGates(const imaging::Match& m) const {
  return m.found && m.peak >= options_.min_peak_correlation &&
         m.second_peak < options_.max_ambiguity_ratio * m.peak &&
         m.curvature >= options_.min_peak_curvature;
}

cv::Point TemplateMatcher::TopLeft(const Eigen::Vector2d& center_px, int t, int level) {
  return {static_cast<int>(center_px.x()) / (1 << level) - t / 2,
          static_cast<int>(center_px.y()) / (1 << level) - t / 2};
}

cv::Mat TemplateMatcher::Template(const cv::Mat& frame, const Eigen::Vector2d& center_px,
                                  int size_px, int level) const {
  const int t = size_px >> level, m = mosaic_->MarginAt(level);
  const cv::Point top_left = TopLeft(center_px, t, level);
  const cv::Rect padded(top_left.x - m, top_left.y - m, t + 2 * m, t + 2 * m);
  if ((padded & cv::Rect(0, 0, frame.cols, frame.rows)) != padded) return {};
  // Normalize with a margin, then crop, so every template pixel sees its whole neighbourhood.
  return mosaic_->Normalize(frame(padded), level)(cv::Rect(m, m, t, t)).clone();
}

std::optional<SiteMatch> TemplateMatcher::Match(const cv::Mat& templ,
                                                const Eigen::Vector2d& center_px, int radius_px,
                                                const FrameMosaicWarp& warp, int level) const {
  if (templ.empty()) return {};
  const int view_size = templ.cols + 2 * radius_px;
  const cv::Mat view =
      RenderNormalizedView(mosaic_,
                           {TopLeft(center_px, templ.cols, level) - cv::Point(radius_px, radius_px),
                            cv::Size(view_size, view_size)},
                           warp.AtLevel(level), level);
  const imaging::Match match = imaging::MatchTemplate(view, templ);
  if (!PassesGates(match)) return {};
  const double scale = 1 << level;
  return SiteMatch{(match.offset_px - Eigen::Vector2d(radius_px, radius_px)) * scale, match};
}

}  // namespace fleetloc::tracking
