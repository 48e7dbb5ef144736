// Does a tracked frame show floor the mosaic does not (a new marking, a repaired slab, an area
// never mapped)? The frame and the mosaic as predicted at the tracked pose are compared block by
// block with normalized cross-correlation; textured blocks that correlate poorly, and blocks the
// mosaic does not cover where the camera sees textured floor, count as changed. The per-block
// comparison is also the map server's evidence when it admits a patch (patch_admission.h).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace fleetloc::mapping {

struct ChangeOptions {
  int block_px = 64;
  double min_block_ncc = 0.3;      // below this a textured block counts as changed (dust: ~0.5)
  double min_block_stddev = 10.0;  // flatter blocks carry no evidence (camera noise dominates)
  int dark_dn = 8;                 // pixels at or below this are darkness, not floor
};

// One block of a frame against the same block of the mosaic view.
struct BlockComparison {
  cv::Rect rect;            // in frame pixels
  bool mapped = false;      // the mosaic covers at least half the block
  bool floor_seen = false;  // 90 % of the frame's pixels are brighter than the dark level
  double frame_stddev = 0;
  double view_stddev = 0;  // when mapped
  double ncc = 0;          // when mapped and either side is textured; 0 when one side is flat
  // Textured on at least one side (so the block says something about the floor).
  bool textured(double min_stddev) const {
    return frame_stddev >= min_stddev || view_stddev >= min_stddev;
  }
};

// Every whole block of `block_px` of the frame, row by row. `frame` and `mosaic_view` are CV_8UC1
// of the same size (the view as RenderPredictedView gives it: 0 outside the mosaic).
std::vector<BlockComparison> CompareBlocks(const cv::Mat& frame, const cv::Mat& mosaic_view,
                                           const ChangeOptions& options = {});

struct ChangeReport {
  int blocks = 0;    // blocks with evidence (textured, or outside the mosaic)
  int changed = 0;   // low correlation
  int unmapped = 0;  // the mosaic has no pixels there
  double changed_fraction() const { return blocks > 0 ? double(changed + unmapped) / blocks : 0.0; }
};

// `frame` and `mosaic_view` as for CompareBlocks.
ChangeReport CompareWithMosaic(const cv::Mat& frame, const cv::Mat& mosaic_view,
                               const ChangeOptions& options = {});

}  // namespace fleetloc::mapping
