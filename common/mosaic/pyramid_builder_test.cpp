// Tests for the strip-wise pyramid builder on real photos: every tile once, level 0 exact, higher
// levels equal to 2×2 area averaging (cv::resize INTER_AREA for even sizes).
#include "mosaic/pyramid_builder.h"

#include <gtest/gtest.h>

#include <map>

#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::SourcePath;

MosaicLayout LayoutFor(const cv::Mat& gray, int tile) {
  MosaicLayout layout;
  layout.width_px = gray.cols;
  layout.height_px = gray.rows;
  layout.tile_size_px = tile;
  layout.levels = PyramidLevelCount(gray.cols, gray.rows, tile);
  return layout;
}

// Runs the builder over all rows of `gray` and returns the tiles it emitted.
std::map<TileKey, cv::Mat> BuildTiles(const cv::Mat& gray, const MosaicLayout& layout) {
  std::map<TileKey, cv::Mat> tiles;
  PyramidBuilder builder(layout, [&](const TileKey& key, const cv::Mat& tile) {
    EXPECT_TRUE(tiles.emplace(key, tile.clone()).second) << "tile emitted twice " << ToString(key);
    return Status::Ok();
  });
  for (int y = 0; y < gray.rows; ++y) {
    EXPECT_TRUE(builder.AddRow({gray.ptr(y), static_cast<std::size_t>(gray.cols)}).ok());
  }
  EXPECT_TRUE(builder.Finish().ok());
  EXPECT_EQ(builder.tiles_emitted(), static_cast<long long>(tiles.size()));
  return tiles;
}

// Pastes the tiles of one level back into an image of the level's size (padding must be zero).
cv::Mat Assemble(const std::map<TileKey, cv::Mat>& tiles, const MosaicLayout& layout, int level) {
  const int t = layout.tile_size_px;
  cv::Mat padded =
      cv::Mat::zeros(TileRows(layout, level) * t, TileColumns(layout, level) * t, CV_8UC1);
  int count = 0;
  for (const auto& [key, tile] : tiles) {
    if (key.level != level) continue;
    tile.copyTo(padded(TilePixelRect(layout, key)));
    ++count;
  }
  EXPECT_EQ(count, TileRows(layout, level) * TileColumns(layout, level));
  const cv::Rect valid(0, 0, layout.LevelWidth(level), layout.LevelHeight(level));
  EXPECT_EQ(cv::countNonZero(padded) - cv::countNonZero(padded(valid)), 0) << "padding not zero";
  return padded(valid).clone();
}

// Independent reference: each pixel is the rounded mean of the existing pixels of its 2×2 block.
cv::Mat HalveByValidPixelMean(const cv::Mat& in) {
  cv::Mat out((in.rows + 1) / 2, (in.cols + 1) / 2, CV_8UC1);
  for (int y = 0; y < out.rows; ++y) {
    for (int x = 0; x < out.cols; ++x) {
      int sum = 0, n = 0;
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
          if (2 * y + dy < in.rows && 2 * x + dx < in.cols) {
            sum += in.at<std::uint8_t>(2 * y + dy, 2 * x + dx);
            ++n;
          }
        }
      }
      out.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>((sum + n / 2) / n);
    }
  }
  return out;
}

TEST(PyramidBuilder, RealPhotoLevelsMatchAreaResize) {
  const cv::Mat gray = LoadGray(SourcePath("tests/data/gravel.png"));  // 512 x 512
  const MosaicLayout layout = LayoutFor(gray, 128);
  ASSERT_EQ(layout.levels, 3);
  const std::map<TileKey, cv::Mat> tiles = BuildTiles(gray, layout);
  EXPECT_EQ(tiles.size(), 16u + 4u + 1u);
  EXPECT_EQ(MaxAbsDiff(Assemble(tiles, layout, 0), gray), 0);
  cv::Mat expected = gray;
  for (int level = 1; level < layout.levels; ++level) {
    cv::resize(expected, expected, {}, 0.5, 0.5, cv::INTER_AREA);
    EXPECT_LE(MaxAbsDiff(Assemble(tiles, layout, level), expected), 1) << "level " << level;
  }
}

TEST(PyramidBuilder, OddSizedCropHasPartialEdgeTilesAndEdgeAverages) {
  const cv::Mat gray = LoadGray(SourcePath("tests/data/brick.png"))(cv::Rect(7, 11, 301, 203));
  const MosaicLayout layout = LayoutFor(gray, 64);  // 301x203 → 151x102 → 76x51 → 38x26
  ASSERT_EQ(layout.levels, 4);
  const std::map<TileKey, cv::Mat> tiles = BuildTiles(gray, layout);
  EXPECT_EQ(MaxAbsDiff(Assemble(tiles, layout, 0), gray), 0);
  cv::Mat expected = gray.clone();
  for (int level = 1; level < layout.levels; ++level) {
    expected = HalveByValidPixelMean(expected);
    EXPECT_EQ(MaxAbsDiff(Assemble(tiles, layout, level), expected), 0) << "level " << level;
  }
}

TEST(PyramidBuilder, DownsampleTileRebuildsEveryUpperTileExactly) {
  const cv::Mat gray = LoadGray(SourcePath("tests/data/brick.png"))(cv::Rect(7, 11, 301, 203));
  const MosaicLayout layout = LayoutFor(gray, 64);
  const std::map<TileKey, cv::Mat> tiles = BuildTiles(gray, layout);
  int checked = 0;
  for (const auto& [key, tile] : tiles) {
    if (key.level == 0) continue;
    const cv::Mat rebuilt =
        DownsampleTile(layout, key, [&](const TileKey& child) { return tiles.at(child); });
    EXPECT_EQ(MaxAbsDiff(rebuilt, tile), 0) << ToString(key);
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

TEST(PyramidBuilder, SinkErrorStopsTheBuild) {
  const cv::Mat gray = LoadGray(SourcePath("tests/data/grass.png"));
  const MosaicLayout layout = LayoutFor(gray, 256);
  int calls = 0;
  PyramidBuilder builder(layout, [&](const TileKey&, const cv::Mat&) {
    ++calls;
    return Internal("disk full");
  });
  Status status;
  for (int y = 0; y < gray.rows && status.ok(); ++y) {
    status = builder.AddRow({gray.ptr(y), static_cast<std::size_t>(gray.cols)});
  }
  EXPECT_EQ(status.message(), "disk full");
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(builder.Finish().ok());
}

}  // namespace
}  // namespace fleetloc::mosaic
