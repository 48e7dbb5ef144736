// TileCache: a thread-safe LRU cache of decoded tiles with a byte bound, shared by the mosaic view
// (reader) and whoever fills it (the store loader, later a DDS tile client).
#pragma once

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <unordered_map>
#include <utility>

#include "mosaic/tile_key.h"

namespace fleetloc::mosaic {

using TilePtr = std::shared_ptr<const cv::Mat>;

struct TileCacheStats {
  long long hits = 0;
  long long misses = 0;
  long long evictions = 0;
  std::size_t entries = 0;
  std::size_t bytes = 0;
};

class TileCache {
 public:
  // `max_bytes` bounds the sum of the cached tiles' pixel bytes (rows × cols × elemSize).
  explicit TileCache(std::size_t max_bytes);

  // Returns the tile and marks it most recently used, or nullptr (counted as a miss).
  TilePtr Get(const TileKey& key);
  // Inserts or replaces a tile as most recently used, then evicts least recently used tiles until
  // the byte bound holds. A tile larger than the whole bound is not cached. Requires tile != null.
  void Put(const TileKey& key, TilePtr tile);
  // Whether the tile is cached (neither counted as a lookup nor moved in the LRU order).
  bool Contains(const TileKey& key) const;
  // Drops one tile (e.g. when a newer version is announced); no effect if absent.
  void Erase(const TileKey& key);
  void Clear();

  TileCacheStats stats() const;
  std::size_t max_bytes() const { return max_bytes_; }

 private:
  using Entry = std::pair<TileKey, TilePtr>;
  using Index = std::unordered_map<TileKey, std::list<Entry>::iterator, TileKeyHash>;
  void EraseLocked(Index::iterator it);  // requires mutex_ held

  const std::size_t max_bytes_;
  mutable std::mutex mutex_;
  std::list<Entry> lru_;  // front = most recently used
  Index index_;
  TileCacheStats stats_;
};

// Bytes a tile accounts for in the cache.
std::size_t TileBytes(const cv::Mat& tile);

}  // namespace fleetloc::mosaic
