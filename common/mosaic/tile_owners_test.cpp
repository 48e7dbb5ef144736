// Tests for tile ownership across map servers: owners per tile at every level, coverage and
// overlap of the servers' ranges.
#include "mosaic/tile_owners.h"

#include <gtest/gtest.h>

#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::Layout;

using Owners = std::vector<std::string>;

TEST(TileOwners, TwoServersSplittingTheColumnsOwnEveryTileOnce) {
  const MosaicLayout layout = Layout(2560, 1600, 256);  // 10 x 7 level-0 tiles
  TileOwners owners;
  owners.Set("ms-west", {0, 5, 0, 7});
  owners.Set("ms-east", {5, 10, 0, 7});
  EXPECT_EQ(owners.UncoveredTiles(layout), 0);
  EXPECT_EQ(owners.OverlappingTiles(layout), 0);
  EXPECT_EQ(owners.OwnersOf({0, 4, 3}), Owners{"ms-west"});
  EXPECT_EQ(owners.OwnersOf({0, 5, 3}), Owners{"ms-east"});
  // Level 1 column 2 starts at level-0 column 4 (west); column 3 at 6 (east).
  EXPECT_EQ(owners.OwnersOf({1, 2, 1}), Owners{"ms-west"});
  EXPECT_EQ(owners.OwnersOf({1, 3, 1}), Owners{"ms-east"});
  EXPECT_EQ(owners.OwnersOf({0, 10, 0}), Owners{});  // outside the grid
  EXPECT_EQ(owners.servers(), 2u);
}

TEST(TileOwners, CountsAGapAndAnOverlap) {
  const MosaicLayout layout = Layout(1024, 1024, 256);  // 4 x 4
  TileOwners owners;
  owners.Set("a", {0, 2, 0, 4});
  owners.Set("b", {3, 4, 0, 4});
  EXPECT_EQ(owners.UncoveredTiles(layout), 4);  // column 2
  owners.Set("b", {1, 4, 0, 4});                // replaces b's range
  EXPECT_EQ(owners.UncoveredTiles(layout), 0);
  EXPECT_EQ(owners.OverlappingTiles(layout), 4);  // column 1
  EXPECT_EQ(owners.OwnersOf({0, 1, 2}), (Owners{"a", "b"}));
  owners.Remove("a");
  EXPECT_EQ(owners.UncoveredTiles(layout), 4);
}

TEST(TileOwners, RangesBeyondTheGridAreClipped) {
  const MosaicLayout layout = Layout(512, 512, 256);  // 2 x 2
  TileOwners owners;
  owners.Set("a", {-3, 50, 1, 70});
  EXPECT_EQ(owners.UncoveredTiles(layout), 2);  // row 0
  EXPECT_EQ(owners.OverlappingTiles(layout), 0);
  EXPECT_EQ(TileOwners{}.UncoveredTiles(layout), 4);
}

}  // namespace
}  // namespace fleetloc::mosaic
