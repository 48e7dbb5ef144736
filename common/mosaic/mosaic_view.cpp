// MosaicView: block assembly from cached tiles.
#include "mosaic/mosaic_view.h"

#include <utility>

namespace fleetloc::mosaic {

MosaicView::MosaicView(MosaicLayout layout, TileLoader loader, std::shared_ptr<TileCache> cache)
    : layout_(std::move(layout)), loader_(std::move(loader)), cache_(std::move(cache)) {
  FLEETLOC_CHECK(loader_ != nullptr && cache_ != nullptr);
  FLEETLOC_CHECK(layout_.tile_size_px > 0 && layout_.levels > 0);
}

cv::Mat AssembleBlock(const MosaicLayout& layout, int level, const cv::Rect& rect, int type,
                      const std::function<TilePtr(const TileKey&)>& fetch) {
  FLEETLOC_CHECK(level >= 0 && level < layout.levels);
  FLEETLOC_CHECK(rect.width >= 0 && rect.height >= 0);
  // Only the pixels no tile fills are zeroed: zeroing the whole block first wrote each pixel twice
  // (6 % of a tracker cycle on a textured floor, measured with callgrind).
  cv::Mat block(rect.size(), type);
  const cv::Rect level_bounds(0, 0, layout.LevelWidth(level), layout.LevelHeight(level));
  const cv::Rect wanted = rect & level_bounds;          // never copy a tile's zero padding
  if (wanted != rect) block.setTo(cv::Scalar::all(0));  // off the level's edge
  TilesCovering(layout, level, wanted).ForEach([&](const TileKey& key) {
    const TilePtr tile = fetch(key);
    const cv::Rect tile_rect = TilePixelRect(layout, key);
    const cv::Rect overlap = tile_rect & wanted;
    if (tile == nullptr) {
      block(overlap - rect.tl()).setTo(cv::Scalar::all(0));
      return;
    }
    (*tile)(overlap - tile_rect.tl()).copyTo(block(overlap - rect.tl()));
  });
  return block;
}

cv::Mat MosaicView::ReadBlock(int level, const cv::Rect& rect) {
  return AssembleBlock(layout_, level, rect, CV_8UC1,
                       [this](const TileKey& key) { return FetchTile(key); });
}

TilePtr MosaicView::FetchTile(const TileKey& key) {
  if (TilePtr cached = cache_->Get(key)) return cached;
  Result<cv::Mat> loaded = loader_(key);
  if (!loaded.ok()) {
    ++(loaded.status().code() == StatusCode::kNotFound ? missing_tiles_ : unreadable_tiles_);
    return nullptr;
  }
  const int t = layout_.tile_size_px;
  if (loaded->type() != CV_8UC1 || loaded->rows != t || loaded->cols != t) {
    ++unreadable_tiles_;
    return nullptr;
  }
  auto tile = std::make_shared<const cv::Mat>(std::move(loaded).value());
  cache_->Put(key, tile);
  return tile;
}

}  // namespace fleetloc::mosaic
