// Tile addressing for the mosaic pyramid: TileKey {level, col, row}, the tile grid of a level and
// the range of tiles covering a pixel rectangle. Pure arithmetic over MosaicLayout.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "mosaic/raster_source.h"

namespace fleetloc::mosaic {

// One tile of the pyramid: level k, column and row of the tile grid of that level.
struct TileKey {
  int level = 0;
  int col = 0;
  int row = 0;

  auto operator<=>(const TileKey&) const = default;  // orders by level, then col, then row
  bool operator==(const TileKey&) const = default;
};

std::string ToString(const TileKey& key);  // "L2/C3/R1", for messages

struct TileKeyHash {
  std::size_t operator()(const TileKey& key) const noexcept;
};

// Number of pyramid levels for a level-0 image of width × height: the smallest count whose top
// level fits in one tile (at least 1). Requires positive sizes.
int PyramidLevelCount(int width_px, int height_px, int tile_size_px);

// Tile columns and rows of `level` (ceil of the level size over the tile size).
int TileColumns(const MosaicLayout& layout, int level);
int TileRows(const MosaicLayout& layout, int level);

// Pixel rectangle (level coordinates) a tile occupies, tile_size × tile_size; edge tiles reach past
// the level's width/height (that part is zero padding).
cv::Rect TilePixelRect(const MosaicLayout& layout, const TileKey& key);

// The tiles of one level whose pixels intersect a rectangle: columns [col_begin, col_end) and rows
// [row_begin, row_end), already clipped to the level's tile grid (empty when nothing overlaps).
struct TileRange {
  int level = 0;
  int col_begin = 0, col_end = 0;
  int row_begin = 0, row_end = 0;

  bool empty() const { return col_begin >= col_end || row_begin >= row_end; }
  int count() const { return empty() ? 0 : (col_end - col_begin) * (row_end - row_begin); }
  // Calls fn(TileKey) for every tile, row by row.
  void ForEach(const std::function<void(const TileKey&)>& fn) const;
};

// Tiles of `level` covering `rect` (pixel coordinates of that level; may lie partly or wholly
// outside the mosaic). Requires 0 <= level < layout.levels.
TileRange TilesCovering(const MosaicLayout& layout, int level, const cv::Rect& rect);

}  // namespace fleetloc::mosaic
