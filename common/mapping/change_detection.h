// Does a tracked frame show floor the mosaic does not (a new marking, a repaired slab, an area
// never mapped)? The frame and the mosaic as predicted at the tracked pose are compared block by
// block with normalized cross-correlation; textured blocks that correlate poorly, and blocks the
// mosaic does not cover where the camera sees textured floor, count as changed.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::mapping {

struct ChangeOptions {
  int block_px = 64;
  double min_block_ncc = 0.3;     // below this a textured block counts as changed (dust: ~0.5)
  double min_block_stddev = 10.0;  // flatter blocks carry no evidence (camera noise dominates)
  int dark_dn = 8;                 // pixels at or below this are darkness, not floor
};

struct ChangeReport {
  int blocks = 0;        // blocks with evidence (textured, or outside the mosaic)
  int changed = 0;       // low correlation
  int unmapped = 0;      // the mosaic has no pixels there
  double changed_fraction() const { return blocks > 0 ? double(changed + unmapped) / blocks : 0.0; }
};

// `frame` and `mosaic_view` are CV_8UC1 of the same size (the view as RenderPredictedView gives
// it: 0 outside the mosaic).
ChangeReport CompareWithMosaic(const cv::Mat& frame, const cv::Mat& mosaic_view,
                               const ChangeOptions& options = {});

}  // namespace fleetloc::mapping
