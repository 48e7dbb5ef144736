// Tests for the row-streaming image I/O: every PNG flavour and PGM/PPM decode to the same gray as
// cv::imread + BGR2GRAY (±1), corrupt files give errors, and the PNG row writer round-trips.
#include "mosaic/row_image_io.h"

#include <gtest/gtest.h>
#include <png.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::ScratchDir;
using testing::SourcePath;

// Reads all rows through the row reader into one image.
cv::Mat ReadAllRows(GrayRowReader& reader) {
  cv::Mat image(reader.height(), reader.width(), CV_8UC1);
  for (int y = 0; y < image.rows; ++y) {
    const Status status = reader.ReadRow({image.ptr(y), static_cast<std::size_t>(image.cols)});
    EXPECT_TRUE(status.ok()) << status.message();
  }
  return image;
}

// Opens `path`, checks whether it streams, and compares its rows with OpenCV's gray (±1).
void ExpectSameGrayAsOpenCv(const std::string& path, bool streaming) {
  Result<std::unique_ptr<GrayRowReader>> reader = OpenGrayRowReader(path);
  ASSERT_TRUE(reader.ok()) << reader.status().message();
  EXPECT_EQ((*reader)->streaming(), streaming) << path;
  EXPECT_LE(MaxAbsDiff(ReadAllRows(**reader), LoadGray(path)), 1) << path;
}

// Writes `rows` (already in the PNG's sample layout) with libpng, to cover flavours OpenCV cannot
// write: palette, gray+alpha, low bit depths, interlacing.
void WritePng(const std::string& path, int width, int height, int bit_depth, int color_type,
              const std::vector<std::vector<png_byte>>& rows, bool interlaced = false,
              const std::vector<png_color>& palette = {}) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, bit_depth, color_type,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  if (!palette.empty()) png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
  std::vector<png_bytep> pointers;
  for (const auto& row : rows) pointers.push_back(const_cast<png_bytep>(row.data()));
  png_set_rows(png, info, pointers.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

// A real photo (colour) as the sample source for synthetic PNG flavours.
cv::Mat PhotoRgb() {
  cv::Mat bgr = cv::imread(SourcePath("deploy/demo/floors/gravel_1024.png"), cv::IMREAD_COLOR);
  cv::Mat rgb;
  cv::cvtColor(bgr(cv::Rect(300, 200, 173, 131)), rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

TEST(GrayRowReader, RealPhotosStreamAndMatchOpenCv) {
  ExpectSameGrayAsOpenCv(SourcePath("tests/data/brick.png"), true);                  // gray
  ExpectSameGrayAsOpenCv(SourcePath("deploy/demo/floors/gravel_1024.png"), true);    // RGBA
  ExpectSameGrayAsOpenCv(SourcePath("deploy/demo/floors/asphalt_1024.jpg"), false);  // JPEG
}

TEST(GrayRowReader, PaletteGrayAlphaSixteenBitLowBitAndInterlacedPngs) {
  ScratchDir dir;
  const cv::Mat rgb = PhotoRgb();
  const int w = rgb.cols, h = rgb.rows;
  std::vector<std::vector<png_byte>> palette_rows(h), ga_rows(h), rgb16_rows(h), gray4_rows(h);
  std::vector<png_color> palette(256);
  for (int i = 0; i < 256; ++i) {
    palette[i] = {static_cast<png_byte>(i), static_cast<png_byte>(255 - i),
                  static_cast<png_byte>(i / 2)};
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const cv::Vec3b p = rgb.at<cv::Vec3b>(y, x);
      palette_rows[y].push_back(p[1]);
      ga_rows[y].insert(ga_rows[y].end(), {p[0], static_cast<png_byte>(x)});
      for (int c = 0; c < 3; ++c) rgb16_rows[y].insert(rgb16_rows[y].end(), {p[c], p[2 - c]});
    }
    for (int x = 0; x < w; x += 2) {
      const int hi = rgb.at<cv::Vec3b>(y, x)[0] >> 4;
      const int lo = x + 1 < w ? rgb.at<cv::Vec3b>(y, x + 1)[0] >> 4 : 0;
      gray4_rows[y].push_back(static_cast<png_byte>(hi << 4 | lo));
    }
  }
  WritePng(dir.File("palette.png"), w, h, 8, PNG_COLOR_TYPE_PALETTE, palette_rows, false, palette);
  WritePng(dir.File("gray_alpha.png"), w, h, 8, PNG_COLOR_TYPE_GRAY_ALPHA, ga_rows);
  WritePng(dir.File("rgb16.png"), w, h, 16, PNG_COLOR_TYPE_RGB, rgb16_rows);
  WritePng(dir.File("gray4.png"), w, h, 4, PNG_COLOR_TYPE_GRAY, gray4_rows);
  WritePng(dir.File("interlaced.png"), w, h, 16, PNG_COLOR_TYPE_RGB, rgb16_rows, true);
  ExpectSameGrayAsOpenCv(dir.File("palette.png"), true);
  ExpectSameGrayAsOpenCv(dir.File("gray_alpha.png"), true);
  ExpectSameGrayAsOpenCv(dir.File("rgb16.png"), true);
  ExpectSameGrayAsOpenCv(dir.File("gray4.png"), true);
  ExpectSameGrayAsOpenCv(dir.File("interlaced.png"), false);
  EXPECT_FALSE(OpenPngRowReader(dir.File("interlaced.png")).ok());
}

TEST(GrayRowReader, BinaryPgmAndPpmStream) {
  ScratchDir dir;
  const cv::Mat bgr = cv::imread(SourcePath("deploy/demo/floors/gravel_1024.png"));
  const cv::Mat crop = bgr(cv::Rect(11, 13, 301, 157));
  cv::Mat gray, deep;
  cv::cvtColor(crop, gray, cv::COLOR_BGR2GRAY);
  crop.convertTo(deep, CV_16U, 257);
  ASSERT_TRUE(cv::imwrite(dir.File("photo.ppm"), crop));
  ASSERT_TRUE(cv::imwrite(dir.File("photo.pgm"), gray));
  ASSERT_TRUE(cv::imwrite(dir.File("photo16.ppm"), deep));
  ExpectSameGrayAsOpenCv(dir.File("photo.ppm"), true);
  ExpectSameGrayAsOpenCv(dir.File("photo.pgm"), true);
  Result<std::unique_ptr<GrayRowReader>> wide = OpenGrayRowReader(dir.File("photo16.ppm"));
  ASSERT_TRUE(wide.ok()) << wide.status().message();
  EXPECT_LE(MaxAbsDiff(ReadAllRows(**wide), gray), 1);
}

TEST(GrayRowReader, CorruptAndMissingFilesGiveErrorsNamingTheFile) {
  ScratchDir dir;
  const std::string bytes = testing::ReadFileBytes(SourcePath("tests/data/grass.png"));
  testing::WriteFileBytes(dir.File("cut.png"), bytes, bytes.size() / 2);
  Result<std::unique_ptr<GrayRowReader>> cut = OpenGrayRowReader(dir.File("cut.png"));
  ASSERT_TRUE(cut.ok()) << cut.status().message();  // the header is intact
  std::vector<std::uint8_t> row((*cut)->width());
  Status status;
  int rows = 0;
  for (; status.ok() && rows < (*cut)->height(); ++rows) status = (*cut)->ReadRow(row);
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput);
  EXPECT_NE(status.message().find(dir.File("cut.png")), std::string::npos) << status.message();
  EXPECT_LT(rows, (*cut)->height());

  testing::WriteFileBytes(dir.File("header.png"), bytes, 20);
  EXPECT_EQ(OpenGrayRowReader(dir.File("header.png")).status().code(), StatusCode::kInvalidInput);
  std::ofstream(dir.File("text.jpg")) << "not an image";
  EXPECT_EQ(OpenGrayRowReader(dir.File("text.jpg")).status().code(), StatusCode::kInvalidInput);
  std::ofstream(dir.File("short.pgm"), std::ios::binary) << "P5\n4 4\n255\nabc";
  Result<std::unique_ptr<GrayRowReader>> pgm = OpenGrayRowReader(dir.File("short.pgm"));
  ASSERT_TRUE(pgm.ok());
  std::vector<std::uint8_t> pgm_row(4);
  EXPECT_EQ((*pgm)->ReadRow(pgm_row).code(), StatusCode::kInvalidInput);
  std::ofstream(dir.File("bad.pgm"), std::ios::binary) << "P5\n4 x\n255\n";
  EXPECT_EQ(OpenGrayRowReader(dir.File("bad.pgm")).status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(OpenGrayRowReader(dir.File("absent.png")).status().code(), StatusCode::kNotFound);
}

TEST(GrayRowWriter, PngWrittenRowByRowReadsBackExactly) {
  ScratchDir dir;
  const cv::Mat gray = LoadGray(SourcePath("tests/data/gravel.png"))(cv::Rect(0, 0, 333, 222));
  Result<std::unique_ptr<GrayRowWriter>> writer =
      CreatePngRowWriter(dir.File("out.png"), gray.cols, gray.rows);
  ASSERT_TRUE(writer.ok()) << writer.status().message();
  for (int y = 0; y < gray.rows; ++y) {
    ASSERT_TRUE((*writer)->WriteRow({gray.ptr(y), static_cast<std::size_t>(gray.cols)}).ok());
  }
  ASSERT_TRUE((*writer)->Finish().ok());
  writer->reset();
  EXPECT_EQ(MaxAbsDiff(cv::imread(dir.File("out.png"), cv::IMREAD_UNCHANGED), gray), 0);
  EXPECT_FALSE(CreatePngRowWriter(dir.File("no/such/dir/out.png"), 10, 10).ok());
}

TEST(GrayRowWriter, PgmRowsReachTheFileAsTheyAreWrittenAndReadBackExactly) {
  ScratchDir dir;
  cv::Mat gray;  // 2 MB: far more than stdio's buffer
  cv::repeat(LoadGray(SourcePath("tests/data/gravel.png"))(cv::Rect(0, 0, 250, 250)), 4, 8, gray);
  const std::string path = dir.File("out.pgm");
  Result<std::unique_ptr<GrayRowWriter>> writer = CreatePgmRowWriter(path, gray.cols, gray.rows);
  ASSERT_TRUE(writer.ok()) << writer.status().message();
  for (int y = 0; y < gray.rows; ++y) {
    ASSERT_TRUE((*writer)->WriteRow({gray.ptr(y), static_cast<std::size_t>(gray.cols)}).ok());
    if (y == gray.rows / 2) {  // streamed: all but stdio's buffer is already in the file
      EXPECT_GE(std::filesystem::file_size(path) + 65536,
                static_cast<std::uintmax_t>(y) * gray.cols);
    }
  }
  ASSERT_TRUE((*writer)->Finish().ok());
  writer->reset();
  EXPECT_EQ(std::filesystem::file_size(path),
            std::string("P5\n2000 1000\n255\n").size() + 2000 * 1000);
  EXPECT_EQ(MaxAbsDiff(cv::imread(path, cv::IMREAD_UNCHANGED), gray), 0);
  Result<std::unique_ptr<GrayRowReader>> reader = OpenGrayRowReader(path);
  ASSERT_TRUE(reader.ok()) << reader.status().message();
  EXPECT_TRUE((*reader)->streaming());
  EXPECT_EQ(MaxAbsDiff(ReadAllRows(**reader), gray), 0);
  EXPECT_FALSE(CreatePgmRowWriter(dir.File("no/such/dir/out.pgm"), 10, 10).ok());
}

}  // namespace
}  // namespace fleetloc::mosaic
