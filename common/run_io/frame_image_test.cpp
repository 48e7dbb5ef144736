// Tests for ReadFrame / ReadGrayImage: exact gray pixels, colour conversion, and errors naming
// the image file for missing, corrupt and wrongly sized frames.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <random>

#include "run_io/run.h"
#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;
using testing::HasError;
using testing::TempDir;

geometry::CameraModel SmallCamera() {
  geometry::CameraModel camera;
  camera.width_px = 16;
  camera.height_px = 12;
  return camera;
}

TEST(ReadFrame, ReadsGrayPngPixelsExactly) {
  TempDir dir;
  const fs::path file = dir.path() / "f.png";
  testing::WriteGrayPng(file, 16, 12);
  Result<cv::Mat> image = ReadFrame({0.0, file}, SmallCamera());
  ASSERT_TRUE(image.ok()) << image.status().message();
  ASSERT_EQ(image->type(), CV_8UC1);
  EXPECT_EQ(image->at<uchar>(0, 0), 0);
  EXPECT_EQ(image->at<uchar>(11, 15), 7 * 15 + 13 * 11);
}

TEST(ReadFrame, ConvertsColourAndSixteenBitPngToEightBitGray) {
  TempDir dir;
  cv::Mat colour(12, 16, CV_8UC3, cv::Scalar(200, 100, 50));  // B, G, R
  ASSERT_TRUE(cv::imwrite((dir.path() / "c.png").string(), colour));
  Result<cv::Mat> gray = ReadFrame({0.0, dir.path() / "c.png"}, SmallCamera());
  ASSERT_TRUE(gray.ok()) << gray.status().message();
  ASSERT_EQ(gray->type(), CV_8UC1);
  // ITU-R BT.601 luma, as cv::cvtColor: 0.299 R + 0.587 G + 0.114 B = 96.4.
  EXPECT_NEAR(gray->at<uchar>(5, 5), 96.4, 1.0);

  cv::Mat deep(12, 16, CV_16UC1, cv::Scalar(40000));
  ASSERT_TRUE(cv::imwrite((dir.path() / "d.png").string(), deep));
  Result<cv::Mat> gray8 = ReadFrame({0.0, dir.path() / "d.png"}, SmallCamera());
  ASSERT_TRUE(gray8.ok()) << gray8.status().message();
  ASSERT_EQ(gray8->type(), CV_8UC1);
  EXPECT_NEAR(gray8->at<uchar>(0, 0), 40000 / 256.0, 1.0);
}

TEST(ReadFrame, MissingFrameIsNotFoundNamingTheFile) {
  TempDir dir;
  const fs::path file = dir.path() / "missing.png";
  EXPECT_TRUE(
      HasError(ReadFrame({0.0, file}, SmallCamera()).status(), StatusCode::kNotFound, file, 0, ""));
}

TEST(ReadFrame, CorruptPngIsInvalidInputNamingTheFile) {
  TempDir dir;
  const fs::path random_file = dir.path() / "random.png";
  std::mt19937 rng(3);
  std::string bytes(4096, '\0');
  for (char& c : bytes) c = static_cast<char>(rng());
  testing::WriteText(random_file, bytes);
  EXPECT_TRUE(HasError(ReadFrame({0.0, random_file}, SmallCamera()).status(),
                       StatusCode::kInvalidInput, random_file, 0, ""));

  // A real PNG signature and header followed by garbage.
  const fs::path valid = dir.path() / "valid.png";
  testing::WriteGrayPng(valid, 16, 12);
  std::string png = testing::ReadText(valid);
  const fs::path broken = dir.path() / "broken.png";
  testing::WriteText(broken, png.substr(0, 33) + bytes.substr(0, 64));
  EXPECT_TRUE(HasError(ReadFrame({0.0, broken}, SmallCamera()).status(), StatusCode::kInvalidInput,
                       broken, 0, ""));
}

TEST(ReadFrame, AHugeImageDeclaredInATinyFileIsRefusedBeforeDecoding) {
  TempDir dir;
  const fs::path file = dir.path() / "huge.png";
  testing::WriteGrayPng(file, 16, 12);
  std::string png = testing::ReadText(file);
  // IHDR width and height (big-endian at 16 and 20) rewritten to 30000 x 30000.
  for (size_t at : {16u, 20u}) {
    png[at] = 0;
    png[at + 1] = 0;
    png[at + 2] = 0x75;
    png[at + 3] = 0x30;
  }
  testing::WriteText(file, png);
  const Status frame = ReadFrame({0.0, file}, SmallCamera()).status();
  EXPECT_TRUE(HasError(frame, StatusCode::kInvalidInput, file, 0, "")) << frame.message();
  EXPECT_NE(frame.message().find("30000x30000"), std::string::npos) << frame.message();
  const Status image = ReadGrayImage(file).status();
  EXPECT_EQ(image.code(), StatusCode::kInvalidInput);
  EXPECT_NE(image.message().find("more than 100000000 pixels"), std::string::npos)
      << image.message();
}

TEST(ReadFrame, WrongSizeNamesFileAndBothSizes) {
  TempDir dir;
  const fs::path file = dir.path() / "big.png";
  testing::WriteGrayPng(file, 20, 12);
  const Status status = ReadFrame({0.0, file}, SmallCamera()).status();
  EXPECT_TRUE(HasError(status, StatusCode::kInvalidInput, file, 0, ""));
  EXPECT_NE(status.message().find("20x12"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("16x12"), std::string::npos) << status.message();
  EXPECT_TRUE(ReadGrayImage(file).ok());
}

}  // namespace
}  // namespace fleetloc::run_io
