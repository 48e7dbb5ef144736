// LRU tile cache with a byte bound.
#include "mosaic/tile_cache.h"

#include "base/status.h"

namespace fleetloc::mosaic {

std::size_t TileBytes(const cv::Mat& tile) { return tile.total() * tile.elemSize(); }

TileCache::TileCache(std::size_t max_bytes) : max_bytes_(max_bytes) {}

TilePtr TileCache::Get(const TileKey& key) {
  std::lock_guard lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) {
    ++stats_.misses;
    return nullptr;
  }
  ++stats_.hits;
  lru_.splice(lru_.begin(), lru_, it->second);
  return it->second->second;
}

void TileCache::Put(const TileKey& key, TilePtr tile) {
  FLEETLOC_CHECK(tile != nullptr);
  const std::size_t bytes = TileBytes(*tile);
  std::lock_guard lock(mutex_);
  if (const auto it = index_.find(key); it != index_.end()) EraseLocked(it);
  if (bytes > max_bytes_) return;
  lru_.emplace_front(key, std::move(tile));
  index_.emplace(key, lru_.begin());
  stats_.bytes += bytes;
  while (stats_.bytes > max_bytes_) {
    EraseLocked(index_.find(lru_.back().first));
    ++stats_.evictions;
  }
  stats_.entries = lru_.size();
}

bool TileCache::Contains(const TileKey& key) const {
  std::lock_guard lock(mutex_);
  return index_.count(key) > 0;
}

void TileCache::Erase(const TileKey& key) {
  std::lock_guard lock(mutex_);
  if (const auto it = index_.find(key); it != index_.end()) EraseLocked(it);
}

void TileCache::Clear() {
  std::lock_guard lock(mutex_);
  lru_.clear();
  index_.clear();
  stats_.bytes = 0;
  stats_.entries = 0;
}

TileCacheStats TileCache::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void TileCache::EraseLocked(Index::iterator it) {
  stats_.bytes -= TileBytes(*it->second->second);
  lru_.erase(it->second);
  index_.erase(it);
  stats_.entries = lru_.size();
}

}  // namespace fleetloc::mosaic
