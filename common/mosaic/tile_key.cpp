// Tile grid arithmetic of the mosaic pyramid.
#include "mosaic/tile_key.h"

#include <algorithm>
#include <cstdio>

#include "base/status.h"

namespace fleetloc::mosaic {
namespace {

int CeilDiv(int a, int b) { return (a + b - 1) / b; }

// Floor division that is correct for negative numerators (pixels left of / above the mosaic).
int FloorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

std::string ToString(const TileKey& key) {
  char text[48];
  std::snprintf(text, sizeof(text), "L%d/C%d/R%d", key.level, key.col, key.row);
  return text;
}

std::size_t TileKeyHash::operator()(const TileKey& key) const noexcept {
  // Levels < 32 and col/row < 2^28 in practice; mix all three into 64 bits.
  const auto h = (static_cast<std::uint64_t>(key.level) << 58) ^
                 (static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.col)) << 29) ^
                 static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.row));
  return std::hash<std::uint64_t>{}(h * 0x9E3779B97F4A7C15ULL);
}

int PyramidLevelCount(int width_px, int height_px, int tile_size_px) {
  FLEETLOC_CHECK(width_px > 0 && height_px > 0 && tile_size_px > 0);
  int levels = 1;
  int w = width_px, h = height_px;
  while (std::max(w, h) > tile_size_px) {
    w = CeilDiv(w, 2);
    h = CeilDiv(h, 2);
    ++levels;
  }
  return levels;
}

int TileColumns(const MosaicLayout& layout, int level) {
  return CeilDiv(layout.LevelWidth(level), layout.tile_size_px);
}

int TileRows(const MosaicLayout& layout, int level) {
  return CeilDiv(layout.LevelHeight(level), layout.tile_size_px);
}

cv::Rect TilePixelRect(const MosaicLayout& layout, const TileKey& key) {
  const int t = layout.tile_size_px;
  return {key.col * t, key.row * t, t, t};
}

void TileRange::ForEach(const std::function<void(const TileKey&)>& fn) const {
  for (int row = row_begin; row < row_end; ++row) {
    for (int col = col_begin; col < col_end; ++col) fn(TileKey{level, col, row});
  }
}

TileRange TilesCovering(const MosaicLayout& layout, int level, const cv::Rect& rect) {
  FLEETLOC_CHECK(level >= 0 && level < layout.levels);
  TileRange range;
  range.level = level;
  if (rect.width <= 0 || rect.height <= 0) return range;
  const int t = layout.tile_size_px;
  range.col_begin = std::max(0, FloorDiv(rect.x, t));
  range.row_begin = std::max(0, FloorDiv(rect.y, t));
  range.col_end = std::min(TileColumns(layout, level), FloorDiv(rect.x + rect.width - 1, t) + 1);
  range.row_end = std::min(TileRows(layout, level), FloorDiv(rect.y + rect.height - 1, t) + 1);
  return range;
}

}  // namespace fleetloc::mosaic
