// Row-streaming reader for binary PGM (P5) and PPM (P6), 8- or 16-bit samples, and writer of 8-bit
// binary PGM.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "mosaic/row_image_io.h"

namespace fleetloc::mosaic {
namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Reads the next header number, skipping whitespace and '#' comments; -1 if there is none.
long ReadHeaderNumber(std::FILE* file) {
  int c = std::fgetc(file);
  while (c == '#' || std::isspace(c)) {
    if (c == '#') {
      while (c != '\n' && c != EOF) c = std::fgetc(file);
    }
    c = std::fgetc(file);
  }
  if (!std::isdigit(c)) return -1;
  long value = 0;
  while (std::isdigit(c) && value < (1L << 30)) {
    value = value * 10 + (c - '0');
    c = std::fgetc(file);
  }
  // The single whitespace character after the last header number ends the header.
  return std::isspace(c) ? value : -1;
}

class PnmRowReader : public GrayRowReader {
 public:
  PnmRowReader(std::string path, File file) : path_(std::move(path)), file_(std::move(file)) {}

  Status Start() {
    char magic[2] = {};
    if (std::fread(magic, 1, 2, file_.get()) != 2 || magic[0] != 'P' ||
        (magic[1] != '5' && magic[1] != '6')) {
      return InvalidInput(path_ + ": not a binary PGM/PPM (P5/P6)");
    }
    channels_ = magic[1] == '6' ? 3 : 1;
    const long width = ReadHeaderNumber(file_.get());
    const long height = ReadHeaderNumber(file_.get());
    maxval_ = ReadHeaderNumber(file_.get());
    if (width <= 0 || height <= 0 || maxval_ <= 0 || maxval_ > 65535) {
      return InvalidInput(path_ + ": PGM/PPM header has no valid width, height and maxval");
    }
    width_px_ = static_cast<int>(width);
    height_px_ = static_cast<int>(height);
    const int sample_bytes = maxval_ > 255 ? 2 : 1;
    raw_.resize(static_cast<std::size_t>(width_px_) * channels_ * sample_bytes);
    samples_.resize(static_cast<std::size_t>(width_px_) * channels_);
    return Status::Ok();
  }

  bool streaming() const override { return true; }

  Status ReadRow(std::span<std::uint8_t> row) override {
    FLEETLOC_CHECK(static_cast<int>(row.size()) == width_px_ && rows_read_ < height_px_);
    if (std::fread(raw_.data(), 1, raw_.size(), file_.get()) != raw_.size()) {
      return InvalidInput(path_ + ": image data ends early at row " + std::to_string(rows_read_));
    }
    ++rows_read_;
    const bool wide = raw_.size() > samples_.size();
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      const long value = wide ? (long{raw_[2 * i]} << 8) | raw_[2 * i + 1] : long{raw_[i]};
      samples_[i] = static_cast<std::uint8_t>(
          maxval_ == 255 ? value : (std::min(value, maxval_) * 255 + maxval_ / 2) / maxval_);
    }
    cv::Mat gray(1, width_px_, CV_8UC1, row.data());
    if (channels_ == 3) {
      cv::cvtColor(cv::Mat(1, width_px_, CV_8UC3, samples_.data()), gray, cv::COLOR_RGB2GRAY);
    } else {
      cv::Mat(1, width_px_, CV_8UC1, samples_.data()).copyTo(gray);
    }
    return Status::Ok();
  }

 private:
  const std::string path_;
  File file_;
  int channels_ = 1;
  long maxval_ = 255;
  int rows_read_ = 0;
  std::vector<std::uint8_t> raw_;      // one row as stored
  std::vector<std::uint8_t> samples_;  // one row scaled to 8 bits
};

// Writes "P5 <width> <height> 255" and then the rows as they come: memory is stdio's buffer only.
class PgmRowWriter : public GrayRowWriter {
 public:
  PgmRowWriter(std::string path, File file, int width_px, int height_px)
      : path_(std::move(path)),
        file_(std::move(file)),
        width_px_(width_px),
        height_px_(height_px) {}

  Status Start() {
    const int written = std::fprintf(file_.get(), "P5\n%d %d\n255\n", width_px_, height_px_);
    return written > 0 ? Status::Ok() : Internal(path_ + ": write failed (PGM header)");
  }

  Status WriteRow(std::span<const std::uint8_t> row) override {
    FLEETLOC_CHECK(static_cast<int>(row.size()) == width_px_ && rows_written_ < height_px_);
    if (std::fwrite(row.data(), 1, row.size(), file_.get()) != row.size()) {
      return Internal(path_ + ": write failed at row " + std::to_string(rows_written_));
    }
    ++rows_written_;
    return Status::Ok();
  }

  Status Finish() override {
    FLEETLOC_CHECK(rows_written_ == height_px_);
    if (std::fflush(file_.get()) != 0 || std::ferror(file_.get())) {
      return Internal(path_ + ": write failed");
    }
    return Status::Ok();
  }

 private:
  const std::string path_;
  File file_;
  const int width_px_, height_px_;
  int rows_written_ = 0;
};

}  // namespace

Result<std::unique_ptr<GrayRowReader>> OpenPnmRowReader(const std::string& path) {
  File file(std::fopen(path.c_str(), "rb"));
  if (file == nullptr) return NotFound(path + ": cannot open for reading");
  auto reader = std::make_unique<PnmRowReader>(path, std::move(file));
  FLEETLOC_RETURN_IF_ERROR(reader->Start());
  return std::unique_ptr<GrayRowReader>(std::move(reader));
}

Result<std::unique_ptr<GrayRowWriter>> CreatePgmRowWriter(const std::string& path, int width_px,
                                                          int height_px) {
  FLEETLOC_CHECK(width_px > 0 && height_px > 0);
  File file(std::fopen(path.c_str(), "wb"));
  if (file == nullptr) return Internal(path + ": cannot create");
  auto writer = std::make_unique<PgmRowWriter>(path, std::move(file), width_px, height_px);
  FLEETLOC_RETURN_IF_ERROR(writer->Start());
  return std::unique_ptr<GrayRowWriter>(std::move(writer));
}

}  // namespace fleetloc::mosaic
