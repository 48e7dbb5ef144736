// Template matching against the mosaic (paper 000 §2.3 and §2.7): for a template site of the
// frame, resample the mosaic around its predicted position into the frame's orientation (the
// heading comes from the prediction; no rotation is searched), normalize both, and find the NCC
// peak within the search radius.
#pragma once

#include <optional>

#include "imaging/correlation.h"
#include "mosaic/raster_source.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

struct SiteMatch {
  Eigen::Vector2d shift_px;  // where the template's content sits in the predicted view, minus
                             // where it sits in the frame (frame pixels)
  imaging::Match quality;
};

class TemplateMatcher {
 public:
  TemplateMatcher(const TrackerOptions& options, mosaic::RasterSource* mosaic);

  // Matches the frame's template centred at `center_px` (integer + T/2 grid) against the mosaic
  // seen through `warp`, searching ±radius_px. Returns nothing when the peak fails a quality gate
  // (value, ambiguity, flatness) or lies on the search border.
  std::optional<SiteMatch> Match(const cv::Mat& frame, const Eigen::Vector2d& center_px,
                                 int radius_px, const FrameMosaicWarp& warp) const;

  // Margin around a template or window needed for normalization, in pixels.
  int margin_px() const { return options_.normalize_window_px / 2 + 1; }

 private:
  bool PassesGates(const imaging::Match& m) const;

  TrackerOptions options_;
  mosaic::RasterSource* mosaic_;
};

}  // namespace fleetloc::tracking
