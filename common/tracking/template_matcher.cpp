// Mosaic resampling, normalization and NCC for one template site.
#include "tracking/template_matcher.h"

#include <opencv2/imgproc.hpp>

#include "imaging/normalize.h"

namespace fleetloc::tracking {

TemplateMatcher::TemplateMatcher(const TrackerOptions& options, mosaic::RasterSource* mosaic)
    : options_(options), mosaic_(mosaic) {}

cv::Mat TemplateMatcher::PredictedView(const cv::Point& top_left, int size_px,
                                       const FrameMosaicWarp& warp) const {
  // Bounding box of the view's corners in the mosaic, with room for interpolation.
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector2d f(top_left.x + (corner & 1) * size_px,
                            top_left.y + (corner >> 1) * size_px);
    const Eigen::Vector2d m = warp(f);
    min_x = std::min(min_x, m.x()), max_x = std::max(max_x, m.x());
    min_y = std::min(min_y, m.y()), max_y = std::max(max_y, m.y());
  }
  const cv::Rect block_rect(static_cast<int>(std::floor(min_x)) - 2,
                            static_cast<int>(std::floor(min_y)) - 2,
                            static_cast<int>(std::ceil(max_x - min_x)) + 5,
                            static_cast<int>(std::ceil(max_y - min_y)) + 5);
  const cv::Mat block = mosaic_->ReadBlock(0, block_rect);
  // View index (i, j) is frame point top_left + (i, j) + 0.5; its block index is
  // warp(frame point) − 0.5 − block origin.
  const Eigen::Vector2d origin =
      warp(Eigen::Vector2d(top_left.x + 0.5, top_left.y + 0.5)) -
      Eigen::Vector2d(0.5 + block_rect.x, 0.5 + block_rect.y);
  const cv::Matx23d view_to_block(warp.linear(0, 0), warp.linear(0, 1), origin.x(),
                                  warp.linear(1, 0), warp.linear(1, 1), origin.y());
  cv::Mat view;
  cv::warpAffine(block, view, view_to_block, {size_px, size_px},
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT);
  return view;
}

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
  const cv::Mat view = PredictedView(top_left - cv::Point(radius_px + m, radius_px + m),
                                     view_size, warp);
  const cv::Mat view_n = imaging::LocalNormalize(view, w)(
      cv::Rect(m, m, view_size - 2 * m, view_size - 2 * m));
  const imaging::Match match = imaging::MatchTemplate(view_n, templ.clone());
  if (!PassesGates(match)) return {};
  return SiteMatch{match.offset_px - Eigen::Vector2d(radius_px, radius_px), match};
}

}  // namespace fleetloc::tracking
