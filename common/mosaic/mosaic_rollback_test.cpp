// Rolling a mosaic back: the new version shows exactly the tiles of the version restored (those
// changed since, every other tile untouched), a dry run writes nothing, and a version that is
// not earlier, or whose tiles were pruned, is refused with nothing written.
#include "mosaic/mosaic_rollback.h"

#include <gtest/gtest.h>

#include <chrono>

#include "mosaic/mosaic_retention.h"
#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

// A tile of one grey level with a mark that tells its key apart.
cv::Mat Tile(int grey, const TileKey& key) {
  cv::Mat tile(64, 64, CV_8UC1, cv::Scalar(grey));
  tile.at<uchar>(key.row, key.col) = static_cast<uchar>(255 - grey);
  return tile;
}

class MosaicRollbackTest : public ::testing::Test {
 protected:
  void SetUp() override {
    MosaicLayout layout = testing::Layout(128, 128, 64);
    layout.geo.resolution = 0.001;
    store_ = std::move(TileStore::Create(path_, layout)).value();
    // Version 1: every level-0 tile grey 10; 2: two of them 20; 3: one of those 30, another 40.
    Write({{{0, 0, 0}, 10}, {{0, 1, 0}, 10}, {{0, 0, 1}, 10}, {{0, 1, 1}, 10}});
    Write({{{0, 0, 0}, 20}, {{0, 1, 0}, 20}});
    Write({{{0, 0, 0}, 30}, {{0, 0, 1}, 40}});
  }
  void Write(const std::vector<std::pair<TileKey, int>>& tiles) {
    ASSERT_TRUE(store_->BeginVersion().ok());
    for (const auto& [key, grey] : tiles) ASSERT_TRUE(store_->PutTile(key, Tile(grey, key)).ok());
    ASSERT_TRUE(store_->CommitVersion().ok());
  }
  int GreyOf(const TileKey& key) { return store_->ReadTile(key)->at<uchar>(10, 10); }

  testing::ScratchDir dir_;
  std::string path_ = dir_.File("floor.db");
  std::unique_ptr<TileStore> store_;
};

TEST_F(MosaicRollbackTest, RestoresTheTilesOfTheEarlierVersionAsANewVersion) {
  Result<RollbackResult> r = RollBackMosaic(*store_, 1, false);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->from_version, 3);
  EXPECT_EQ(r->new_version, 4);
  EXPECT_EQ(r->tiles, (std::vector<TileKey>{{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}));
  EXPECT_EQ(store_->version(), 4);
  for (const TileKey& key : {TileKey{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}}) {
    EXPECT_EQ(GreyOf(key), 10) << ToString(key);
    EXPECT_EQ(store_->ReadTile(key)->at<uchar>(key.row, key.col), 245) << ToString(key);
  }
  // The undone versions stay readable until pruned.
  EXPECT_EQ(store_->ReadTileBytesAt({0, 0, 0}, 3).ok(), true);
}

TEST_F(MosaicRollbackTest, GoesBackOneVersion) {
  Result<RollbackResult> r = RollBackMosaic(*store_, 2, false);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->tiles, (std::vector<TileKey>{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_EQ(GreyOf({0, 0, 0}), 20);
  EXPECT_EQ(GreyOf({0, 0, 1}), 10);
  EXPECT_EQ(GreyOf({0, 1, 0}), 20);
}

TEST_F(MosaicRollbackTest, ADryRunListsTheTilesAndWritesNothing) {
  Result<RollbackResult> r = RollBackMosaic(*store_, 1, true);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->tiles.size(), 3u);
  EXPECT_EQ(r->new_version, 3);
  EXPECT_EQ(*store_->Refresh(), 3);
  EXPECT_EQ(GreyOf({0, 0, 0}), 30);
}

TEST_F(MosaicRollbackTest, RefusesAVersionThatIsNotEarlierOrWasPruned) {
  for (const long long bad : {0LL, 3LL, 7LL, -1LL}) {
    Result<RollbackResult> r = RollBackMosaic(*store_, bad, false);
    EXPECT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.status().message().find("not an earlier version"), std::string::npos)
        << r.status().message();
  }
  RetentionPolicy keep_two;
  keep_two.tile_versions_kept = 2;  // versions 2 and 3
  ASSERT_TRUE(PruneMosaic(path_, keep_two, 1e9).ok());
  Result<RollbackResult> pruned = RollBackMosaic(*store_, 1, false);
  ASSERT_FALSE(pruned.ok());
  EXPECT_NE(pruned.status().message().find("no longer stored"), std::string::npos)
      << pruned.status().message();
  EXPECT_EQ(*store_->Refresh(), 3);
  EXPECT_EQ(GreyOf({0, 0, 0}), 30);
  EXPECT_TRUE(RollBackMosaic(*store_, 2, false).ok());  // still kept
}

}  // namespace
}  // namespace fleetloc::mosaic
