// Does a tracked frame show floor the mosaic does not (a new marking, a repaired slab, an area
// never mapped)? The frame and the mosaic as predicted at the tracked pose are compared block by
// block with normalized cross-correlation; textured blocks that correlate poorly, and blocks the
// mosaic does not cover, count as changed.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::mapping {

struct ChangeOptions {
  int block_px = 64;
  double min_block_ncc = 0.5;     // below this a textured block counts as changed
  double min_block_stddev = 4.0;  // flatter blocks (in both images) carry no evidence
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
