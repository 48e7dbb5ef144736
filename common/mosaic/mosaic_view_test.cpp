// Tests for MosaicView over tiles of a real photo: blocks equal the image (level 0) and its area
// resize (level 1) at random rects, across tile borders and outside; missing tiles leave zeros.
#include "mosaic/mosaic_view.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

#include "mosaic/pyramid_builder.h"
#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::SourcePath;

// Tiles of a real photo held in memory, served by a loader that counts its calls.
struct InMemoryMosaic {
  explicit InMemoryMosaic(const std::string& photo, int tile_size) {
    gray = LoadGray(SourcePath(photo));
    layout.mosaic_id = "test";
    layout.width_px = gray.cols;
    layout.height_px = gray.rows;
    layout.tile_size_px = tile_size;
    layout.levels = PyramidLevelCount(gray.cols, gray.rows, tile_size);
    PyramidBuilder builder(layout, [this](const TileKey& key, const cv::Mat& tile) {
      tiles[key] = tile.clone();
      return Status::Ok();
    });
    for (int y = 0; y < gray.rows; ++y) {
      EXPECT_TRUE(builder.AddRow({gray.ptr(y), static_cast<std::size_t>(gray.cols)}).ok());
    }
  }
  TileLoader Loader() {
    return [this](const TileKey& key) -> Result<cv::Mat> {
      ++loads;
      const auto it = tiles.find(key);
      if (it == tiles.end()) return NotFound("no tile " + ToString(key));
      return it->second;
    };
  }
  cv::Mat gray;
  MosaicLayout layout;
  std::map<TileKey, cv::Mat> tiles;
  int loads = 0;
};

TEST(MosaicView, RandomBlocksEqualTheImageAndItsAreaResize) {
  InMemoryMosaic mosaic("tests/data/gravel.png", 128);  // 512 x 512, 4 x 4 tiles at level 0
  MosaicView view(mosaic.layout, mosaic.Loader(), std::make_shared<TileCache>(8 << 20));
  cv::Mat level1;
  cv::resize(mosaic.gray, level1, {}, 0.5, 0.5, cv::INTER_AREA);
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> pos(-100, 520), size(1, 200);
  for (int i = 0; i < 200; ++i) {
    const cv::Rect rect(pos(rng), pos(rng), size(rng), size(rng));
    EXPECT_EQ(MaxAbsDiff(view.ReadBlock(0, rect), CopyBlockWithZeroBorder(mosaic.gray, rect)), 0)
        << rect;
    const cv::Rect half(rect.x / 2, rect.y / 2, rect.width, rect.height);
    EXPECT_LE(MaxAbsDiff(view.ReadBlock(1, half), CopyBlockWithZeroBorder(level1, half)), 1)
        << half;
  }
  EXPECT_EQ(view.missing_tiles(), 0);
  EXPECT_EQ(view.unreadable_tiles(), 0);
}

TEST(MosaicView, BlockSpanningFourTilesLoadsEachTileOnceThenHitsTheCache) {
  InMemoryMosaic mosaic("tests/data/brick.png", 128);
  MosaicView view(mosaic.layout, mosaic.Loader(), std::make_shared<TileCache>(8 << 20));
  const cv::Rect across(100, 100, 60, 60);  // corner of tiles (0,0), (1,0), (0,1), (1,1)
  const cv::Mat first = view.ReadBlock(0, across);
  EXPECT_EQ(mosaic.loads, 4);
  const cv::Mat second = view.ReadBlock(0, across);
  EXPECT_EQ(mosaic.loads, 4);
  EXPECT_EQ(MaxAbsDiff(first, second), 0);
  EXPECT_EQ(MaxAbsDiff(first, mosaic.gray(across)), 0);
  EXPECT_EQ(view.cache().stats().hits, 4);
}

TEST(MosaicView, WhollyOutsideBlockIsZeroWithoutLoads) {
  InMemoryMosaic mosaic("tests/data/grass.png", 256);
  MosaicView view(mosaic.layout, mosaic.Loader(), std::make_shared<TileCache>(1 << 20));
  const cv::Mat block = view.ReadBlock(0, {-400, 600, 50, 30});
  EXPECT_EQ(block.size(), cv::Size(50, 30));
  EXPECT_EQ(cv::countNonZero(block), 0);
  EXPECT_EQ(mosaic.loads, 0);
}

TEST(MosaicView, MissingAndUnreadableTilesLeaveZerosAndAreCounted) {
  InMemoryMosaic mosaic("tests/data/gravel.png", 128);
  mosaic.tiles.erase({0, 1, 0});                       // missing
  mosaic.tiles[{0, 0, 1}] = cv::Mat(64, 64, CV_8UC1);  // wrong size: unreadable
  MosaicView view(mosaic.layout, mosaic.Loader(), std::make_shared<TileCache>(8 << 20));
  const cv::Mat block = view.ReadBlock(0, {0, 0, 256, 256});
  EXPECT_EQ(cv::countNonZero(block(cv::Rect(128, 0, 128, 128))), 0);
  EXPECT_EQ(cv::countNonZero(block(cv::Rect(0, 128, 128, 128))), 0);
  EXPECT_EQ(MaxAbsDiff(block(cv::Rect(0, 0, 128, 128)), mosaic.gray(cv::Rect(0, 0, 128, 128))), 0);
  EXPECT_EQ(view.missing_tiles(), 1);
  EXPECT_EQ(view.unreadable_tiles(), 1);

  // The block's memory is not zeroed in advance: a missing tile's pixels are zeroed even where
  // the allocator hands back memory that held another block's pixels.
  for (int i = 0; i < 5; ++i) {
    { const cv::Mat textured = view.ReadBlock(0, {256, 256, 256, 256}); }
    const cv::Mat reused = view.ReadBlock(0, {0, 0, 256, 256});
    EXPECT_EQ(cv::countNonZero(reused(cv::Rect(128, 0, 128, 128))), 0);
  }

  MosaicView failing(
      mosaic.layout,
      [](const TileKey&) -> Result<cv::Mat> {
        return Internal("database disk image is malformed");
      },
      std::make_shared<TileCache>(1 << 20));
  EXPECT_EQ(cv::countNonZero(failing.ReadBlock(1, {0, 0, 256, 256})), 0);
  EXPECT_EQ(failing.unreadable_tiles(), 4);
}

}  // namespace
}  // namespace fleetloc::mosaic
