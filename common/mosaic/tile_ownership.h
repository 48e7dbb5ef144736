// Which tiles a map server answers for when the mosaic is split across servers: a rectangle of
// level-0 tiles; a tile of level k belongs to the server owning its top-left level-0 tile, so
// every tile has exactly one owner when the servers' rectangles partition the grid.
#pragma once

#include "mosaic/tile_key.h"

namespace fleetloc::mosaic {

struct TileOwnership {
  int col_begin = 0, col_end = 0;  // level-0 tile columns [begin, end)
  int row_begin = 0, row_end = 0;  // level-0 tile rows [begin, end)

  // The whole level-0 tile grid of `layout`.
  static TileOwnership All(const MosaicLayout& layout) {
    return {0, TileColumns(layout, 0), 0, TileRows(layout, 0)};
  }
  bool Owns(const TileKey& key) const {
    const int col0 = key.col << key.level, row0 = key.row << key.level;
    return col0 >= col_begin && col0 < col_end && row0 >= row_begin && row0 < row_end;
  }
  bool empty() const { return col_begin >= col_end || row_begin >= row_end; }
  bool operator==(const TileOwnership&) const = default;
};

}  // namespace fleetloc::mosaic
