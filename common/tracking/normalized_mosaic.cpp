// Normalized mosaic tiles, computed once per tile with a margin from the neighbouring tiles.
#include "tracking/normalized_mosaic.h"

#include <cmath>

#include "imaging/fast_patch.h"
#include "imaging/gaussian_blur.h"
#include "mosaic/mosaic_view.h"

namespace fleetloc::tracking {

namespace {

int SmoothingRadius(double sigma_px) { return static_cast<int>(std::ceil(2.0 * sigma_px)); }

}  // namespace

NormalizedMosaic::NormalizedMosaic(mosaic::RasterSource* mosaic, int window_level0_px,
                                   size_t cache_bytes, double level0_sigma_px)
    : mosaic_(mosaic),
      window_level0_px_(window_level0_px),
      level0_sigma_px_(level0_sigma_px),
      cache_(std::make_unique<mosaic::TileCache>(cache_bytes)) {}

cv::Mat NormalizedMosaic::Normalize(const cv::Mat& image, int level,
                                    cv::Mat* local_variance) const {
  cv::Mat normalized =
      imaging::NormalizePatch(image, WindowAt(level), kSpreadEpsilon, local_variance);
  if (level == 0 && level0_sigma_px_ > 0) {
    // Only the pixels the whole kernel covers are smoothed: the others lie within MarginAt(0),
    // which no caller uses.
    const int r = SmoothingRadius(level0_sigma_px_);
    if (normalized.cols > 2 * r && normalized.rows > 2 * r) {
      imaging::GaussianBlurInterior(normalized, level0_sigma_px_, r)
          .copyTo(normalized(cv::Rect(r, r, normalized.cols - 2 * r, normalized.rows - 2 * r)));
    }
  }
  return normalized;
}

int NormalizedMosaic::MarginAt(int level) const {
  return WindowAt(level) / 2 + 1 + (level == 0 ? SmoothingRadius(level0_sigma_px_) : 0);
}

mosaic::TilePtr NormalizedMosaic::NormalizedTile(const mosaic::TileKey& key) {
  if (mosaic::TilePtr cached = cache_->Get(key)) return cached;
  const int margin = MarginAt(key.level);
  const cv::Rect tile = mosaic::TilePixelRect(layout(), key);
  const cv::Rect padded(tile.x - margin, tile.y - margin, tile.width + 2 * margin,
                        tile.height + 2 * margin);
  const cv::Mat normalized = Normalize(mosaic_->ReadBlock(key.level, padded), key.level);
  auto result = std::make_shared<const cv::Mat>(
      normalized(cv::Rect(margin, margin, tile.width, tile.height)).clone());
  cache_->Put(key, result);
  return result;
}

bool NormalizedMosaic::Prepare(const mosaic::TileKey& key) {
  if (cache_->Contains(key)) return false;
  (void)NormalizedTile(key);
  return true;
}

cv::Mat NormalizedMosaic::ReadBlock(int level, const cv::Rect& rect) {
  return mosaic::AssembleBlock(layout(), level, rect, CV_32F,
                               [this](const mosaic::TileKey& k) { return NormalizedTile(k); });
}

}  // namespace fleetloc::tracking
