// FloorComposer: a floor texture of any size (up to gigapixels) made of square blocks cut from a
// few real floor photographs, rendered one block row at a time so it is never held whole. Each
// block has its own photo, crop, orientation and gain, all drawn from the seed and the block's
// grid position, so any block row can be rendered alone and a seed always gives the same floor.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "base/status.h"

namespace fleetloc::sim {

struct FloorComposerOptions {
  int width_px = 0;    // > 0
  int height_px = 0;   // > 0
  int block_px = 512;  // side of a block; every photo must be at least this large both ways
  std::uint64_t seed = 1;
  double max_gain_change = 0.15;  // block gains are drawn from [1 - this, 1 + this], in [0, 0.5]
  // Non-repeating floor (for place recognition): each block is also rotated by an arbitrary angle
  // and scaled by a factor drawn from [min_scale, max_scale] (photo pixels per floor pixel), so
  // the photos' content, reused across the floor, never appears twice at the same orientation
  // and scale. Off: blocks are axis-aligned crops in one of the 8 right-angle orientations, and
  // the same photo region recurs in the same orientation (an ambiguous floor).
  bool free_rotation_and_scale = false;
  double min_scale = 0.8;   // > 0
  double max_scale = 1.25;  // >= min_scale; photos must be >= block_px · max_scale · √2 + 4
};

// Range checks of the options; InvalidInput naming the field.
Status Validate(const FloorComposerOptions& options);

// Where a block's pixels come from. The block is the block_px square of `photo` at `crop_origin`,
// transposed if `transpose`, then mirrored left-right if `flip_x` and top-bottom if `flip_y`, and
// every pixel multiplied by `gain` (rounded, saturated). With free_rotation_and_scale the block is
// instead photo pixel `center` + scale · R(angle) · (block pixel − block centre), bilinear,
// mirrored left-right if `flip_x`, then the gain.
struct BlockPlacement {
  int photo = 0;
  cv::Point crop_origin;
  cv::Point2d center;
  double angle_rad = 0.0;
  double scale = 1.0;
  bool transpose = false;
  bool flip_x = false;
  bool flip_y = false;
  double gain = 1.0;
};

class FloorComposer {
 public:
  // Validates the options and the photos (at least one; each CV_8UC1 and at least block_px on
  // both sides). InvalidInput naming the photo's index or the option otherwise.
  static Result<FloorComposer> Create(std::vector<cv::Mat> photos, FloorComposerOptions options);

  const FloorComposerOptions& options() const { return options_; }
  int block_rows() const {
    return (options_.height_px + options_.block_px - 1) / options_.block_px;
  }
  int block_cols() const { return (options_.width_px + options_.block_px - 1) / options_.block_px; }

  // The placement of block (col, row) of the block grid. The eight neighbours of a block always
  // differ from it in orientation (the four parities of (col, row) get disjoint orientation
  // pairs), so no two neighbouring blocks are the same pixels even when they share a photo.
  BlockPlacement PlacementOf(int col, int row) const;

  // The block_px square of block (col, row), before clipping to the floor.
  cv::Mat RenderBlock(int col, int row) const;

  // Floor rows [row * block_px, min((row + 1) * block_px, height)) across the whole width
  // (CV_8UC1). Memory: one block row, block_px × width bytes. Requires 0 <= row < block_rows().
  cv::Mat RenderBlockRow(int row) const;

 private:
  FloorComposer(std::vector<cv::Mat> photos, FloorComposerOptions options);
  cv::Mat RenderFreeBlock(const BlockPlacement& placement) const;  // before the gain

  std::vector<cv::Mat> photos_;
  FloorComposerOptions options_;
};

}  // namespace fleetloc::sim
