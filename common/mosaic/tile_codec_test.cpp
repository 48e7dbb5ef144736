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

TEST(TileCodec, DepthAndChannelsAreRefusedFromTheHeaderBeforeDecoding) {
  // A 16-bit RGBA patch: refused on what its header declares.
  std::vector<std::uint8_t> rgba16;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(240, 320, CV_16UC4, cv::Scalar(1, 2, 3, 4)), rgba16));
  const Status refused = CheckGrayPngHeader(rgba16, 4096);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidInput);
  EXPECT_NE(refused.message().find("320x240, 16-bit, 4 channels; it must be 8-bit gray"),
            std::string::npos)
      << refused.message();
  EXPECT_EQ(DecodeGrayPng(rgba16, 4096).status().message(), refused.message());
  // A header declaring 30000 x 30000 in a few bytes: refused by size, nothing decoded.
  std::vector<std::uint8_t> huge = *EncodeTile(cv::Mat(2, 2, CV_8UC1, cv::Scalar(0)));
  for (size_t at : {16u, 20u}) {
    huge[at] = 0;
    huge[at + 1] = 0;
    huge[at + 2] = 0x75;
    huge[at + 3] = 0x30;
  }
  EXPECT_NE(DecodeGrayPng(huge, 4096).status().message().find("30000x30000 px"), std::string::npos);
  EXPECT_TRUE(CheckGrayPngHeader(*EncodeTile(RealTile()), 256).ok());
}

}  // namespace
}  // namespace fleetloc::mosaic
