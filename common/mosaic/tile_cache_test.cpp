// Tests for the LRU tile cache: byte bound, LRU order, counters and concurrent use.
#include "mosaic/tile_cache.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace fleetloc::mosaic {
namespace {

TilePtr Tile(int size, int value) {
  return std::make_shared<const cv::Mat>(size, size, CV_8UC1, cv::Scalar(value));
}

TEST(TileCache, EvictsLeastRecentlyUsedToStayWithinByteBound) {
  TileCache cache(3 * 64 * 64);  // room for three 64x64 tiles
  cache.Put({0, 0, 0}, Tile(64, 1));
  cache.Put({0, 1, 0}, Tile(64, 2));
  cache.Put({0, 2, 0}, Tile(64, 3));
  ASSERT_NE(cache.Get({0, 0, 0}), nullptr);  // now (0,0,0) is most recent; (0,1,0) is least
  cache.Put({0, 3, 0}, Tile(64, 4));
  EXPECT_EQ(cache.Get({0, 1, 0}), nullptr);
  EXPECT_NE(cache.Get({0, 0, 0}), nullptr);
  EXPECT_NE(cache.Get({0, 2, 0}), nullptr);
  EXPECT_EQ(cache.Get({0, 3, 0})->at<std::uint8_t>(0, 0), 4);
  const TileCacheStats stats = cache.stats();
  EXPECT_EQ(stats.evictions, 1);
  EXPECT_EQ(stats.entries, 3u);
  EXPECT_EQ(stats.bytes, 3u * 64 * 64);
  EXPECT_EQ(stats.hits, 4);
  EXPECT_EQ(stats.misses, 1);
}

TEST(TileCache, MixedSizesEvictUntilBoundHolds) {
  TileCache cache(100 * 100);
  cache.Put({0, 0, 0}, Tile(50, 1));  // 2500
  cache.Put({0, 1, 0}, Tile(50, 2));  // 5000
  cache.Put({0, 2, 0}, Tile(50, 3));  // 7500
  cache.Put({1, 0, 0}, Tile(80, 4));  // +6400 → evict two 50s → 8900
  const TileCacheStats stats = cache.stats();
  EXPECT_LE(stats.bytes, cache.max_bytes());
  EXPECT_EQ(stats.bytes, 2500u + 6400u);
  EXPECT_EQ(stats.evictions, 2);
  EXPECT_NE(cache.Get({0, 2, 0}), nullptr);
}

TEST(TileCache, ReplacingATileUpdatesBytesAndOversizedTilesAreNotKept) {
  TileCache cache(64 * 64);
  cache.Put({0, 0, 0}, Tile(32, 1));
  cache.Put({0, 0, 0}, Tile(64, 2));
  EXPECT_EQ(cache.stats().bytes, 64u * 64);
  EXPECT_EQ(cache.Get({0, 0, 0})->at<std::uint8_t>(0, 0), 2);
  cache.Put({0, 1, 0}, Tile(65, 3));  // larger than the whole cache
  EXPECT_EQ(cache.Get({0, 1, 0}), nullptr);
  EXPECT_EQ(cache.stats().entries, 1u);
  cache.Erase({0, 0, 0});
  EXPECT_EQ(cache.stats().bytes, 0u);
  cache.Put({0, 2, 0}, Tile(16, 1));
  cache.Clear();
  EXPECT_EQ(cache.stats().entries, 0u);
}

TEST(TileCache, HandedOutTilesSurviveEviction) {
  TileCache cache(32 * 32);
  cache.Put({0, 0, 0}, Tile(32, 7));
  const TilePtr held = cache.Get({0, 0, 0});
  cache.Put({0, 1, 0}, Tile(32, 8));  // evicts (0,0,0)
  EXPECT_EQ(held->at<std::uint8_t>(5, 5), 7);
}

TEST(TileCache, ConcurrentReadersAndWritersKeepTheBound) {
  TileCache cache(20 * 32 * 32);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&cache, t] {
      for (int i = 0; i < 2000; ++i) {
        const TileKey key{0, (i * 7 + t) % 50, t};
        if (TilePtr tile = cache.Get(key)) {
          EXPECT_EQ(tile->at<std::uint8_t>(0, 0), key.col);
        } else {
          cache.Put(key, Tile(32, key.col));
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  const TileCacheStats stats = cache.stats();
  EXPECT_LE(stats.bytes, cache.max_bytes());
  EXPECT_EQ(stats.bytes, stats.entries * 32 * 32);
  EXPECT_EQ(stats.hits + stats.misses, 4 * 2000);
}

}  // namespace
}  // namespace fleetloc::mosaic
