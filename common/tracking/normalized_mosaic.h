// The locally normalized mosaic (paper 000 §2.4: "and optionally mosaic images"): each tile of a
// pyramid level is normalized once, with the margin its neighbours provide, and kept as floats in
// a byte-bounded LRU cache, so the hot loop only resamples already normalized pixels. At full
// resolution the normalized pixels are also smoothed (TrackerOptions::match_smoothing_sigma_px);
// Normalize() treats frame images the same way, so both sides of every match agree.
#pragma once

#include <memory>

#include "mosaic/raster_source.h"
#include "mosaic/tile_cache.h"
#include "mosaic/tile_key.h"

namespace fleetloc::tracking {

class NormalizedMosaic {
 public:
  // `mosaic` must outlive this. window_px(level) is the normalization window at each level;
  // level 0 is then smoothed with a Gaussian of `level0_sigma_px` (0: not).
  NormalizedMosaic(mosaic::RasterSource* mosaic, int window_level0_px, size_t cache_bytes,
                   double level0_sigma_px = 0.0);

  // `image` (a frame or part of one, at `level`) normalized exactly as the mosaic is. Pixels
  // within MarginAt(level) of its border see only part of their neighbourhood. `local_variance`,
  // when given, receives the image's variance over the normalization window.
  cv::Mat Normalize(const cv::Mat& image, int level, cv::Mat* local_variance = nullptr) const;
  // Normalize divides each pixel's offset from its window's mean by (its spread + this).
  static constexpr float kSpreadEpsilon = 2.0f;
  int MarginAt(int level) const;

  // CV_32F normalized pixels of `rect` at `level`; outside the mosaic 0.
  cv::Mat ReadBlock(int level, const cv::Rect& rect);
  // Normalizes the tile now unless it is cached: true when it did (ahead-of-use work).
  bool Prepare(const mosaic::TileKey& key);
  int WindowAt(int level) const { return WindowAt(window_level0_px_, level); }
  // A window of `window_level0_px` at level 0 scaled to `level` (odd, at least 5).
  static int WindowAt(int window_level0_px, int level) {
    return std::max(5, (window_level0_px >> level) | 1);
  }
  const mosaic::MosaicLayout& layout() const { return mosaic_->layout(); }
  mosaic::RasterSource* source() const { return mosaic_; }  // the mosaic's own pixels
  mosaic::TileCache& cache() { return *cache_; }

 private:
  mosaic::TilePtr NormalizedTile(const mosaic::TileKey& key);

  mosaic::RasterSource* mosaic_;
  int window_level0_px_;
  double level0_sigma_px_;
  std::unique_ptr<mosaic::TileCache> cache_;
};

}  // namespace fleetloc::tracking
