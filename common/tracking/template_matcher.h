// Template matching against the mosaic (paper 000 §2.3 and §2.7): the normalized template of a
// frame site is correlated with the normalized mosaic resampled around its predicted position in
// the frame's orientation (the heading comes from the prediction; no rotation is searched).
// Works at pyramid level 0 (full resolution) or a coarser level of both frame and mosaic for a
// cheap first search of large windows.
#pragma once

#include <optional>

#include "imaging/correlation.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/normalized_mosaic.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

struct SiteMatch {
  Eigen::Vector2d shift_px;  // where the template's content sits in the predicted view, minus
                             // where it sits in the frame (level-0 frame pixels)
  imaging::Match quality;
};

class TemplateMatcher {
 public:
  // `mosaic` must outlive the matcher.
  TemplateMatcher(const TrackerOptions& options, NormalizedMosaic* mosaic);

  // The normalized template of the site centred at level-0 frame point `center_px` (on the
  // candidate grid), size_px level-0 pixels square, cut from the frame at `level`; empty if it
  // does not fit in the frame.
  cv::Mat Template(const cv::Mat& frame_at_level, const Eigen::Vector2d& center_px, int size_px,
                   int level) const;

  // Matches a template from Template() against the mosaic seen through `warp` (level 0 → level
  // 0), searching ±radius_px pixels of `level`. Returns nothing when the peak fails a quality
  // gate (value, ambiguity, flatness) or lies on the search border.
  std::optional<SiteMatch> Match(const cv::Mat& templ, const Eigen::Vector2d& center_px,
                                 int radius_px, const FrameMosaicWarp& warp, int level) const;

  // Margin around a template needed for its normalization, in level-0 pixels.
  int margin_px() const { return mosaic_->WindowAt(0) / 2 + 1; }

 private:
  bool PassesGates(const imaging::Match& m) const;
  static cv::Point TopLeft(const Eigen::Vector2d& center_px, int size_at_level, int level);

  TrackerOptions options_;
  NormalizedMosaic* mosaic_;
};

}  // namespace fleetloc::tracking
