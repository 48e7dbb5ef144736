// PyramidBuilder: turns level-0 image rows, fed top to bottom, into every tile of the pyramid with
// bounded memory — one strip of tile_size rows per level (about 2 × width × tile_size bytes).
// Level k is the 2×2 area average of level k-1 (edge pixels average the pixels that exist).
#pragma once

#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

#include "base/status.h"
#include "mosaic/raster_source.h"
#include "mosaic/tile_key.h"

namespace fleetloc::mosaic {

// One row of level k+1 from one or two rows of level k (`b` null: a single last row): each output
// pixel is the rounded mean of the 2×2 (or fewer, at the level's edge) input pixels that exist.
// `width` is level k's width; writes (width + 1) / 2 pixels to `out`.
void AverageRowPair(const std::uint8_t* a, const std::uint8_t* b, int width, std::uint8_t* out);

// Recomputes tile `parent` (level >= 1) from the level below exactly as PyramidBuilder does:
// `child(key)` returns each of the (up to four) child tiles (CV_8UC1, tile size; zeros where the
// mosaic has none). Pixels past the level's edge are 0.
cv::Mat DownsampleTile(const MosaicLayout& layout, const TileKey& parent,
                       const std::function<cv::Mat(const TileKey&)>& child);

class PyramidBuilder {
 public:
  // Receives each finished tile (CV_8UC1, tile_size square, zero padded past the level's edge).
  // The Mat is only valid during the call. A non-ok Status stops the build and is returned by
  // AddRow.
  using TileSink = std::function<Status(const TileKey&, const cv::Mat&)>;

  // Requires layout sizes > 0, an even tile size and levels == PyramidLevelCount(...).
  PyramidBuilder(const MosaicLayout& layout, TileSink sink);

  // Adds the next level-0 row (exactly layout.width_px gray pixels). Tiles are emitted as soon as
  // their strip is complete. Requires fewer than height_px rows added so far.
  Status AddRow(std::span<const std::uint8_t> row);
  // Checks that all height_px rows were added (and therefore all tiles emitted).
  Status Finish() const;

  long long tiles_emitted() const { return tiles_emitted_; }

 private:
  struct Level {
    cv::Mat strip;  // tile_size rows × level width
    int rows_in_strip = 0;
    int strip_index = 0;                 // tile row of the strip
    int rows_done = 0;                   // rows of this level received so far
    std::vector<std::uint8_t> down_row;  // scratch row for the next level
  };

  Status AddRowToLevel(int level, std::span<const std::uint8_t> row);
  // Averages strip rows [first, first + count) (count 1 or 2) horizontally by pairs into the next
  // level's row and adds it there.
  Status PushDown(int level, int first_row, int count);
  Status EmitStrip(int level);

  MosaicLayout layout_;
  TileSink sink_;
  std::vector<Level> levels_;
  long long tiles_emitted_ = 0;
};

}  // namespace fleetloc::mosaic
