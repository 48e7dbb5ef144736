// Strip-wise pyramid construction.
#include "mosaic/pyramid_builder.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace fleetloc::mosaic {

PyramidBuilder::PyramidBuilder(const MosaicLayout& layout, TileSink sink)
    : layout_(layout), sink_(std::move(sink)) {
  FLEETLOC_CHECK(layout_.width_px > 0 && layout_.height_px > 0);
  FLEETLOC_CHECK(layout_.tile_size_px > 0 && layout_.tile_size_px % 2 == 0);
  FLEETLOC_CHECK(layout_.levels ==
                 PyramidLevelCount(layout_.width_px, layout_.height_px, layout_.tile_size_px));
  levels_.resize(layout_.levels);
  for (int k = 0; k < layout_.levels; ++k) {
    levels_[k].strip = cv::Mat::zeros(layout_.tile_size_px, layout_.LevelWidth(k), CV_8UC1);
    if (k + 1 < layout_.levels) levels_[k].down_row.resize(layout_.LevelWidth(k + 1));
  }
}

Status PyramidBuilder::AddRow(std::span<const std::uint8_t> row) {
  FLEETLOC_CHECK(static_cast<int>(row.size()) == layout_.width_px);
  FLEETLOC_CHECK(levels_[0].rows_done < layout_.height_px);
  return AddRowToLevel(0, row);
}

Status PyramidBuilder::Finish() const {
  if (levels_[0].rows_done != layout_.height_px) {
    return Internal("pyramid builder: got " + std::to_string(levels_[0].rows_done) + " of " +
                    std::to_string(layout_.height_px) + " rows");
  }
  return Status::Ok();
}

Status PyramidBuilder::AddRowToLevel(int level, std::span<const std::uint8_t> row) {
  Level& l = levels_[level];
  std::memcpy(l.strip.ptr(l.rows_in_strip), row.data(), row.size());
  ++l.rows_in_strip;
  ++l.rows_done;
  const bool last_row = l.rows_done == layout_.LevelHeight(level);
  const bool has_next = level + 1 < layout_.levels;
  // Strips hold an even number of rows, so a row pair never straddles two strips.
  if (has_next && l.rows_in_strip % 2 == 0) {
    FLEETLOC_RETURN_IF_ERROR(PushDown(level, l.rows_in_strip - 2, 2));
  } else if (has_next && last_row) {
    FLEETLOC_RETURN_IF_ERROR(PushDown(level, l.rows_in_strip - 1, 1));
  }
  if (l.rows_in_strip == layout_.tile_size_px || last_row) return EmitStrip(level);
  return Status::Ok();
}

void AverageRowPair(const std::uint8_t* a, const std::uint8_t* b, int width, std::uint8_t* out) {
  const int count = b != nullptr ? 2 : 1;
  for (int i = 0; 2 * i < width; ++i) {
    const int x0 = 2 * i;
    const int x1 = std::min(x0 + 1, width - 1);
    const int n = (x1 - x0 + 1) * count;  // pixels that exist: 4, 2 or 1
    int sum = a[x0] + (x1 != x0 ? a[x1] : 0);
    if (count == 2) sum += b[x0] + (x1 != x0 ? b[x1] : 0);
    out[i] = static_cast<std::uint8_t>((sum + n / 2) / n);
  }
}

cv::Mat DownsampleTile(const MosaicLayout& layout, const TileKey& parent,
                       const std::function<cv::Mat(const TileKey&)>& child) {
  FLEETLOC_CHECK(parent.level >= 1 && parent.level < layout.levels);
  const int t = layout.tile_size_px, below = parent.level - 1;
  // The level-below pixels under the parent, clipped to that level's size.
  const cv::Rect source = cv::Rect(2 * parent.col * t, 2 * parent.row * t, 2 * t, 2 * t) &
                          cv::Rect(0, 0, layout.LevelWidth(below), layout.LevelHeight(below));
  cv::Mat block = cv::Mat::zeros(2 * t, 2 * t, CV_8UC1);
  for (int dy = 0; dy < 2; ++dy) {
    for (int dx = 0; dx < 2; ++dx) {
      const TileKey key{below, 2 * parent.col + dx, 2 * parent.row + dy};
      if (key.col * t >= layout.LevelWidth(below) || key.row * t >= layout.LevelHeight(below))
        continue;
      child(key).copyTo(block(cv::Rect(dx * t, dy * t, t, t)));
    }
  }
  cv::Mat tile = cv::Mat::zeros(t, t, CV_8UC1);
  for (int y = 0; y < source.height; y += 2) {
    const std::uint8_t* a = block.ptr(y);
    const std::uint8_t* b = y + 1 < source.height ? block.ptr(y + 1) : nullptr;
    AverageRowPair(a, b, source.width, tile.ptr(y / 2));
  }
  return tile;
}

Status PyramidBuilder::PushDown(int level, int first_row, int count) {
  Level& l = levels_[level];
  AverageRowPair(l.strip.ptr(first_row), count == 2 ? l.strip.ptr(first_row + 1) : nullptr,
                 layout_.LevelWidth(level), l.down_row.data());
  return AddRowToLevel(level + 1, l.down_row);
}

Status PyramidBuilder::EmitStrip(int level) {
  Level& l = levels_[level];
  const int t = layout_.tile_size_px;
  const int width = layout_.LevelWidth(level);
  cv::Mat tile(t, t, CV_8UC1);
  for (int col = 0; col * t < width; ++col) {
    tile.setTo(0);
    const cv::Rect src(col * t, 0, std::min(t, width - col * t), l.rows_in_strip);
    l.strip(src).copyTo(tile(cv::Rect(0, 0, src.width, src.height)));
    FLEETLOC_RETURN_IF_ERROR(sink_(TileKey{level, col, l.strip_index}, tile));
    ++tiles_emitted_;
  }
  l.rows_in_strip = 0;
  ++l.strip_index;
  return Status::Ok();
}

}  // namespace fleetloc::mosaic
