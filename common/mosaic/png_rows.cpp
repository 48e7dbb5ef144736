// Row-streaming PNG reading and writing with libpng. libpng reports errors by longjmp; every
// libpng call runs inside PngProtected, whose frames hold no objects with destructors, and the
// error becomes a Status.
#include <png.h>

#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "mosaic/row_image_io.h"

namespace fleetloc::mosaic {
namespace {

struct PngError {
  char message[256] = "unknown libpng error";
};

void OnPngError(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(error->message, sizeof(error->message), "%s", message);
  png_longjmp(png, 1);
}

void OnPngWarning(png_structp, png_const_charp) {}  // e.g. "iCCP: known incorrect profile"

// Runs fn (libpng calls only); false if libpng raised an error.
template <typename Fn>
bool PngProtected(png_structp png, Fn&& fn) {
  if (setjmp(png_jmpbuf(png))) return false;
  fn();
  return true;
}

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Asks libpng for 8-bit gray or RGB rows whatever the stored format.
void SetGrayOrRgbTransforms(png_structp png, png_infop info) {
  const png_byte color_type = png_get_color_type(png, info);
  const png_byte bit_depth = png_get_bit_depth(png, info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (bit_depth == 16) png_set_strip_16(png);  // high byte, as OpenCV's decoder does
  if (color_type & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
}

class PngRowReader : public GrayRowReader {
 public:
  PngRowReader(std::string path, File file) : path_(std::move(path)), file_(std::move(file)) {}
  ~PngRowReader() override { png_destroy_read_struct(&png_, &info_, nullptr); }

  Status Start() {
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error_, OnPngError, OnPngWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (info_ == nullptr) return Internal(path_ + ": libpng initialisation failed");
    png_uint_32 width = 0, height = 0;
    int interlace = 0;
    const bool ok = PngProtected(png_, [&] {
      png_init_io(png_, file_.get());
      png_set_user_limits(png_, 0x7fffffff, 0x7fffffff);
      png_read_info(png_, info_);
      width = png_get_image_width(png_, info_);
      height = png_get_image_height(png_, info_);
      interlace = png_get_interlace_type(png_, info_);
      SetGrayOrRgbTransforms(png_, info_);
      png_read_update_info(png_, info_);
    });
    if (!ok) return InvalidInput(path_ + ": not a readable PNG (" + error_.message + ")");
    if (interlace != PNG_INTERLACE_NONE) {
      return InvalidInput(path_ + ": interlaced PNG cannot be read row by row");
    }
    width_px_ = static_cast<int>(width);
    height_px_ = static_cast<int>(height);
    channels_ = png_get_channels(png_, info_);
    decoded_.resize(png_get_rowbytes(png_, info_));
    return Status::Ok();
  }

  bool streaming() const override { return true; }

  Status ReadRow(std::span<std::uint8_t> row) override {
    FLEETLOC_CHECK(static_cast<int>(row.size()) == width_px_ && rows_read_ < height_px_);
    png_bytep decoded = decoded_.data();
    if (!PngProtected(png_, [&] { png_read_row(png_, decoded, nullptr); })) {
      return InvalidInput(path_ + ": PNG data corrupt at row " + std::to_string(rows_read_) + " (" +
                          error_.message + ")");
    }
    ++rows_read_;
    cv::Mat gray(1, width_px_, CV_8UC1, row.data());
    if (channels_ == 3) {
      cv::cvtColor(cv::Mat(1, width_px_, CV_8UC3, decoded), gray, cv::COLOR_RGB2GRAY);
    } else {
      cv::Mat(1, width_px_, CV_8UC1, decoded).copyTo(gray);
    }
    return Status::Ok();
  }

 private:
  const std::string path_;
  File file_;
  PngError error_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  int channels_ = 1;
  int rows_read_ = 0;
  std::vector<std::uint8_t> decoded_;
};

class PngRowWriter : public GrayRowWriter {
 public:
  PngRowWriter(std::string path, File file, int width_px, int height_px)
      : path_(std::move(path)),
        file_(std::move(file)),
        width_px_(width_px),
        height_px_(height_px) {}
  ~PngRowWriter() override { png_destroy_write_struct(&png_, &info_); }

  Status Start() {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error_, OnPngError, OnPngWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (info_ == nullptr) return Internal(path_ + ": libpng initialisation failed");
    return Check(PngProtected(png_, [&] {
      png_init_io(png_, file_.get());
      png_set_IHDR(png_, info_, width_px_, height_px_, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                   PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
      png_write_info(png_, info_);
    }));
  }

  Status WriteRow(std::span<const std::uint8_t> row) override {
    FLEETLOC_CHECK(static_cast<int>(row.size()) == width_px_ && rows_written_ < height_px_);
    ++rows_written_;
    png_const_bytep data = row.data();
    return Check(PngProtected(png_, [&] { png_write_row(png_, data); }));
  }

  Status Finish() override {
    FLEETLOC_CHECK(rows_written_ == height_px_);
    FLEETLOC_RETURN_IF_ERROR(Check(PngProtected(png_, [&] { png_write_end(png_, nullptr); })));
    if (std::fflush(file_.get()) != 0 || std::ferror(file_.get())) {
      return Internal(path_ + ": write failed");
    }
    return Status::Ok();
  }

 private:
  Status Check(bool ok) const {
    return ok ? Status::Ok() : Internal(path_ + ": PNG writing failed (" + error_.message + ")");
  }

  const std::string path_;
  File file_;
  const int width_px_, height_px_;
  PngError error_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  int rows_written_ = 0;
};

}  // namespace

Result<std::unique_ptr<GrayRowReader>> OpenPngRowReader(const std::string& path) {
  File file(std::fopen(path.c_str(), "rb"));
  if (file == nullptr) return NotFound(path + ": cannot open for reading");
  auto reader = std::make_unique<PngRowReader>(path, std::move(file));
  FLEETLOC_RETURN_IF_ERROR(reader->Start());
  return std::unique_ptr<GrayRowReader>(std::move(reader));
}

Result<std::unique_ptr<GrayRowWriter>> CreatePngRowWriter(const std::string& path, int width_px,
                                                          int height_px) {
  FLEETLOC_CHECK(width_px > 0 && height_px > 0);
  File file(std::fopen(path.c_str(), "wb"));
  if (file == nullptr) return Internal(path + ": cannot create");
  auto writer = std::make_unique<PngRowWriter>(path, std::move(file), width_px, height_px);
  FLEETLOC_RETURN_IF_ERROR(writer->Start());
  return std::unique_ptr<GrayRowWriter>(std::move(writer));
}

}  // namespace fleetloc::mosaic
