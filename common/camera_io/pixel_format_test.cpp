// ToGray: each supported format gives the gray values of a known image; bad buffers are named.
#include "camera_io/pixel_format.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace fleetloc::camera_io {
namespace {

cv::Mat Ramp() {
  cv::Mat gray(6, 8, CV_8UC1);
  for (int r = 0; r < gray.rows; ++r)
    for (int c = 0; c < gray.cols; ++c)
      gray.at<uint8_t>(r, c) = static_cast<uint8_t>(10 * c + 30 * r);
  return gray;
}

TEST(PixelFormat, MonoFormatsKeepTheGrayValues) {
  const cv::Mat gray = Ramp();
  auto mono8 = ToGray(gray.data, gray.total(), 8, 6, "Mono8");
  ASSERT_TRUE(mono8.ok());
  EXPECT_EQ(cv::norm(*mono8, gray, cv::NORM_INF), 0);
  cv::Mat mono12;
  gray.convertTo(mono12, CV_16U, 16);  // 12 significant bits
  auto from12 = ToGray(mono12.data, mono12.total() * 2, 8, 6, "Mono12");
  ASSERT_TRUE(from12.ok());
  EXPECT_EQ(cv::norm(*from12, gray, cv::NORM_INF), 0);
}

TEST(PixelFormat, RgbBecomesItsLuma) {
  cv::Mat rgb(6, 8, CV_8UC3, cv::Scalar(200, 100, 50));  // R, G, B in buffer order
  auto gray = ToGray(rgb.data, rgb.total() * 3, 8, 6, "RGB8");
  ASSERT_TRUE(gray.ok());
  EXPECT_NEAR(gray->at<uint8_t>(3, 3), 0.299 * 200 + 0.587 * 100 + 0.114 * 50, 1.0);
}

TEST(PixelFormat, UnsupportedFormatsAndShortBuffersAreNamed) {
  const cv::Mat gray = Ramp();
  auto yuv = ToGray(gray.data, gray.total(), 8, 6, "YUV422_8");
  ASSERT_FALSE(yuv.ok());
  EXPECT_EQ(yuv.status().message(), "pixel format YUV422_8 is not supported");
  auto short_buffer = ToGray(gray.data, gray.total() - 1, 8, 6, "Mono8");
  ASSERT_FALSE(short_buffer.ok());
  EXPECT_EQ(short_buffer.status().message(), "a Mono8 buffer of 47 bytes for 8x6 (needs 48)");
}

}  // namespace
}  // namespace fleetloc::camera_io
