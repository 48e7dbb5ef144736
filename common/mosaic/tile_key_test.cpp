// Tests for tile addressing: level counts, tile grids and the tiles covering a rectangle.
#include "mosaic/tile_key.h"

#include <gtest/gtest.h>

#include <set>
#include <unordered_set>

#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::Layout;

TEST(TileKey, PyramidTopLevelFitsInOneTile) {
  EXPECT_EQ(PyramidLevelCount(256, 256, 256), 1);
  EXPECT_EQ(PyramidLevelCount(257, 10, 256), 2);
  EXPECT_EQ(PyramidLevelCount(2048, 2048, 256), 4);  // 2048, 1024, 512, 256
  EXPECT_EQ(PyramidLevelCount(2560, 1600, 256), 5);  // top level 160 x 100
  EXPECT_EQ(PyramidLevelCount(513, 513, 256), 3);    // 513 → 257 → 129
}

TEST(TileKey, GridOfOddSizedLevelsRoundsUp) {
  const MosaicLayout layout = Layout(1000, 600, 256);  // levels: 1000x600, 500x300, 250x150
  ASSERT_EQ(layout.levels, 3);
  EXPECT_EQ(TileColumns(layout, 0), 4);
  EXPECT_EQ(TileRows(layout, 0), 3);
  EXPECT_EQ(TileColumns(layout, 1), 2);
  EXPECT_EQ(TileRows(layout, 1), 2);
  EXPECT_EQ(TileColumns(layout, 2), 1);
  EXPECT_EQ(TilePixelRect(layout, {1, 1, 1}), cv::Rect(256, 256, 256, 256));
}

TEST(TileKey, CoveringRangeAcrossBordersAndPartlyOutside) {
  const MosaicLayout layout = Layout(1000, 600, 256);
  // Exactly one tile, then one pixel more on each side.
  TileRange one = TilesCovering(layout, 0, {256, 256, 256, 256});
  EXPECT_EQ(one.count(), 1);
  EXPECT_EQ(one.col_begin, 1);
  TileRange grown = TilesCovering(layout, 0, {255, 255, 258, 258});
  EXPECT_EQ(grown.col_begin, 0);
  EXPECT_EQ(grown.col_end, 3);
  EXPECT_EQ(grown.count(), 9);
  // Partly outside at the top-left and bottom-right: clipped to the grid.
  TileRange corner = TilesCovering(layout, 0, {-300, -10, 310, 20});
  EXPECT_EQ(corner.col_begin, 0);
  EXPECT_EQ(corner.col_end, 1);
  EXPECT_EQ(corner.row_end, 1);
  TileRange far = TilesCovering(layout, 0, {900, 500, 500, 500});
  EXPECT_EQ(far.col_begin, 3);
  EXPECT_EQ(far.col_end, 4);
  EXPECT_EQ(far.row_end, 3);
  // Wholly outside or empty.
  EXPECT_TRUE(TilesCovering(layout, 0, {-50, 0, 50, 50}).empty());
  EXPECT_TRUE(TilesCovering(layout, 0, {1024, 0, 10, 10}).empty());
  EXPECT_TRUE(TilesCovering(layout, 0, {10, 10, 0, 10}).empty());
}

TEST(TileKey, ForEachVisitsEveryTileOnce) {
  const MosaicLayout layout = Layout(1000, 600, 256);
  std::set<TileKey> seen;
  TilesCovering(layout, 1, {0, 0, 500, 300}).ForEach([&](const TileKey& key) {
    EXPECT_TRUE(seen.insert(key).second);
  });
  EXPECT_EQ(seen, (std::set<TileKey>{{1, 0, 0}, {1, 0, 1}, {1, 1, 0}, {1, 1, 1}}));
}

TEST(TileKey, HashAndOrderingDistinguishAllKeysOfAGrid) {
  std::unordered_set<TileKey, TileKeyHash> keys;
  std::set<TileKey> ordered;
  for (int level = 0; level < 4; ++level) {
    for (int col = 0; col < 40; ++col) {
      for (int row = 0; row < 40; ++row) {
        keys.insert({level, col, row});
        ordered.insert({level, col, row});
      }
    }
  }
  EXPECT_EQ(keys.size(), 4u * 40 * 40);
  EXPECT_EQ(ordered.size(), keys.size());
  EXPECT_LT((TileKey{0, 5, 9}), (TileKey{1, 0, 0}));
  EXPECT_EQ(ToString({2, 3, 1}), "L2/C3/R1");
}

}  // namespace
}  // namespace fleetloc::mosaic
