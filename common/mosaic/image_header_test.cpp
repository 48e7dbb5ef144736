// Image headers: size, depth and channels read from PNG, JPEG and PNM bytes as OpenCV writes them,
// and a tiny file declaring a huge image is seen as such without decoding.
#include "mosaic/image_header.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace fleetloc::mosaic {
namespace {

std::vector<std::uint8_t> Encode(const cv::Mat& image, const char* ext) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes));
  return bytes;
}

TEST(ImageHeader, ReadsSizeDepthAndChannelsOfEncodedImages) {
  struct Case {
    cv::Mat image;
    const char* ext;
    ImageFormat format;
    int depth, channels;
  };
  const Case cases[] = {
      {cv::Mat(12, 16, CV_8UC1, cv::Scalar(7)), ".png", ImageFormat::kPng, 8, 1},
      {cv::Mat(12, 16, CV_16UC4, cv::Scalar(7, 7, 7, 7)), ".png", ImageFormat::kPng, 16, 4},
      {cv::Mat(12, 16, CV_8UC3, cv::Scalar(1, 2, 3)), ".png", ImageFormat::kPng, 8, 3},
      {cv::Mat(12, 16, CV_8UC3, cv::Scalar(1, 2, 3)), ".jpg", ImageFormat::kJpeg, 8, 3},
      {cv::Mat(12, 16, CV_8UC1, cv::Scalar(9)), ".jpg", ImageFormat::kJpeg, 8, 1},
      {cv::Mat(12, 16, CV_8UC1, cv::Scalar(9)), ".pgm", ImageFormat::kPnm, 8, 1},
      {cv::Mat(12, 16, CV_8UC3, cv::Scalar(9, 9, 9)), ".ppm", ImageFormat::kPnm, 8, 3},
      {cv::Mat(12, 16, CV_8UC3, cv::Scalar(9, 9, 9)), ".bmp", ImageFormat::kBmp, 8, 3},
  };
  for (const Case& c : cases) {
    const std::optional<ImageHeader> h = ReadImageHeader(Encode(c.image, c.ext));
    ASSERT_TRUE(h.has_value()) << c.ext;
    EXPECT_EQ(h->format, c.format) << c.ext;
    EXPECT_EQ(h->width, 16) << c.ext;
    EXPECT_EQ(h->height, 12) << c.ext;
    EXPECT_EQ(h->bit_depth, c.depth) << c.ext;
    EXPECT_EQ(h->channels, c.channels) << c.ext;
  }
}

TEST(ImageHeader, ATinyFileDeclaringAHugeImageIsReadAsDeclared) {
  std::vector<std::uint8_t> png = Encode(cv::Mat(2, 2, CV_8UC1, cv::Scalar(0)), ".png");
  // IHDR width and height (big-endian at 16 and 20) rewritten to 30000 × 30000.
  for (size_t at : {16u, 20u}) {
    png[at] = 0;
    png[at + 1] = 0;
    png[at + 2] = 0x75;
    png[at + 3] = 0x30;
  }
  const std::optional<ImageHeader> h = ReadImageHeader(png);
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->pixels(), 900'000'000LL);
  EXPECT_EQ(h->Describe(), "30000x30000, 8-bit, 1 channel");
}

TEST(ImageHeader, OtherBytesHaveNoHeader) {
  for (const std::string text : {"", "GIF89a....", "P5 16", "\xff\xd8\xff", "\x89PNG\r\n\x1a\n"}) {
    EXPECT_FALSE(ReadImageHeader({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()})
                     .has_value())
        << text;
  }
}

}  // namespace
}  // namespace fleetloc::mosaic
