// MosaicView: the RasterSource over a tiled mosaic. Assembles coherent pixel blocks of any level
// from tiles held in a shared TileCache, loading misses through a TileLoader (the SQLite store
// today, a DDS tile client later).
#pragma once

#include <atomic>
#include <functional>
#include <memory>

#include "base/status.h"
#include "mosaic/raster_source.h"
#include "mosaic/tile_cache.h"
#include "mosaic/tile_key.h"

namespace fleetloc::mosaic {

// Fetches one decoded tile (CV_8UC1, tile_size × tile_size). NotFound when the mosaic has no such
// tile; any other error when it exists but cannot be read. Must be callable from any thread.
using TileLoader = std::function<Result<cv::Mat>(const TileKey&)>;

// Assembles the pixels of `rect` (level coordinates) from tiles of `type` given by `fetch`
// (nullptr: no tile, left as zeros). Shared by every tiled raster.
cv::Mat AssembleBlock(const MosaicLayout& layout, int level, const cv::Rect& rect, int type,
                      const std::function<TilePtr(const TileKey&)>& fetch);

class MosaicView : public RasterSource {
 public:
  // `cache` may be shared with other views of the same mosaic version; requires loader and cache.
  MosaicView(MosaicLayout layout, TileLoader loader, std::shared_ptr<TileCache> cache);

  const MosaicLayout& layout() const override { return layout_; }
  // See RasterSource. Requires 0 <= level < layout().levels and a non-negative rect size.
  // Tiles that are missing or unreadable leave zeros and are counted.
  cv::Mat ReadBlock(int level, const cv::Rect& rect) override;

  long long missing_tiles() const { return missing_tiles_; }        // loader said NotFound
  long long unreadable_tiles() const { return unreadable_tiles_; }  // other failures, bad tiles
  TileCache& cache() { return *cache_; }

 private:
  // The tile from the cache or the loader; nullptr (and a counter bumped) when unavailable.
  TilePtr FetchTile(const TileKey& key);

  MosaicLayout layout_;
  TileLoader loader_;
  std::shared_ptr<TileCache> cache_;
  std::atomic<long long> missing_tiles_{0};
  std::atomic<long long> unreadable_tiles_{0};
};

}  // namespace fleetloc::mosaic
