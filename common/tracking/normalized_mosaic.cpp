// Normalized mosaic tiles, computed once per tile with a margin from the neighbouring tiles.
#include "tracking/normalized_mosaic.h"

#include "imaging/fast_patch.h"
#include "mosaic/mosaic_view.h"

namespace fleetloc::tracking {

NormalizedMosaic::NormalizedMosaic(mosaic::RasterSource* mosaic, int window_level0_px,
                                   size_t cache_bytes)
    : mosaic_(mosaic),
      window_level0_px_(window_level0_px),
      cache_(std::make_unique<mosaic::TileCache>(cache_bytes)) {}

mosaic::TilePtr NormalizedMosaic::NormalizedTile(const mosaic::TileKey& key) {
  if (mosaic::TilePtr cached = cache_->Get(key)) return cached;
  const int margin = WindowAt(key.level) / 2 + 1;
  const cv::Rect tile = mosaic::TilePixelRect(layout(), key);
  const cv::Rect padded(tile.x - margin, tile.y - margin, tile.width + 2 * margin,
                        tile.height + 2 * margin);
  const cv::Mat normalized = imaging::NormalizePatch(mosaic_->ReadBlock(key.level, padded),
                                                     WindowAt(key.level));
  auto result = std::make_shared<const cv::Mat>(
      normalized(cv::Rect(margin, margin, tile.width, tile.height)).clone());
  cache_->Put(key, result);
  return result;
}

cv::Mat NormalizedMosaic::ReadBlock(int level, const cv::Rect& rect) {
  return mosaic::AssembleBlock(layout(), level, rect, CV_32F, [this](const mosaic::TileKey& k) {
    return NormalizedTile(k);
  });
}

}  // namespace fleetloc::tracking
