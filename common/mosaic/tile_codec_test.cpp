// Tests for the PNG tile codec: exact round trip of a real tile, and clean errors (no crash) for
// corrupt bytes, wrong sizes and wrong pixel types.
#include "mosaic/tile_codec.h"

#include <gtest/gtest.h>

#include <random>

#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::SourcePath;

cv::Mat RealTile() {
  return LoadGray(SourcePath("tests/data/gravel.png"))(cv::Rect(100, 50, 256, 256)).clone();
}

TEST(TileCodec, RealTileRoundTripsExactly) {
  const cv::Mat tile = RealTile();
  Result<std::vector<std::uint8_t>> png = EncodeTile(tile);
  ASSERT_TRUE(png.ok()) << png.status().message();
  EXPECT_LT(png->size(), 256u * 256u);  // compressed
  Result<cv::Mat> decoded = DecodeTile(*png, 256);
  ASSERT_TRUE(decoded.ok()) << decoded.status().message();
  EXPECT_EQ(MaxAbsDiff(*decoded, tile), 0);
}

TEST(TileCodec, CorruptBytesAreRejectedNotCrashing) {
  const std::vector<std::uint8_t> png = *EncodeTile(RealTile());
  EXPECT_EQ(DecodeTile({}, 256).status().code(), StatusCode::kInvalidInput);
  const std::vector<std::uint8_t> text = {'h', 'e', 'l', 'l', 'o'};
  EXPECT_EQ(DecodeTile(text, 256).status().code(), StatusCode::kInvalidInput);
  for (const std::size_t keep : {8ul, 30ul, 100ul, png.size() / 2, png.size() - 13}) {
    const std::vector<std::uint8_t> truncated(png.begin(), png.begin() + keep);
    EXPECT_FALSE(DecodeTile(truncated, 256).ok()) << "kept " << keep << " bytes";
  }
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {  // flipped bytes in the compressed data
    std::vector<std::uint8_t> damaged = png;
    for (int k = 0; k < 8; ++k) damaged[40 + rng() % (damaged.size() - 40)] ^= 0x5a;
    Result<cv::Mat> decoded = DecodeTile(damaged, 256);  // must not crash; may decode garbage
    if (decoded.ok()) {
      EXPECT_EQ(decoded->size(), cv::Size(256, 256));
    }
  }
}

TEST(TileCodec, WrongSizeAndTypeAreRejected) {
  const cv::Mat tile = RealTile();
  Result<cv::Mat> wrong_size = DecodeTile(*EncodeTile(tile), 128);
  EXPECT_EQ(wrong_size.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(wrong_size.status().message().find("256x256, expected 128x128"), std::string::npos);

  std::vector<std::uint8_t> colour;
  cv::Mat bgr;
  cv::cvtColor(tile, bgr, cv::COLOR_GRAY2BGR);
  ASSERT_TRUE(cv::imencode(".png", bgr, colour));
  EXPECT_EQ(DecodeTile(colour, 256).status().code(), StatusCode::kInvalidInput);

  std::vector<std::uint8_t> deep;
  cv::Mat wide;
  tile.convertTo(wide, CV_16U, 256);
  ASSERT_TRUE(cv::imencode(".png", wide, deep));
  EXPECT_EQ(DecodeTile(deep, 256).status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace fleetloc::mosaic
