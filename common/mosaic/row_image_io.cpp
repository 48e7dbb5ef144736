// Choice of image decoder by file content, and the whole-image fallback through OpenCV.
#include "mosaic/row_image_io.h"

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetloc::mosaic {
namespace {

// Serves rows of an image decoded whole by cv::imread. Used for formats without a streaming
// decoder here (JPEG, TIFF, WebP, interlaced PNG, ASCII PNM, ...): peak memory is then the whole
// decoded image, which bounds the image size to what the machine can hold.
class DecodedRowReader : public GrayRowReader {
 public:
  explicit DecodedRowReader(cv::Mat gray) : gray_(std::move(gray)) {
    width_px_ = gray_.cols;
    height_px_ = gray_.rows;
  }
  bool streaming() const override { return false; }
  Status ReadRow(std::span<std::uint8_t> row) override {
    FLEETLOC_CHECK(static_cast<int>(row.size()) == width_px_ && next_row_ < height_px_);
    std::memcpy(row.data(), gray_.ptr(next_row_++), row.size());
    return Status::Ok();
  }

 private:
  cv::Mat gray_;
  int next_row_ = 0;
};

Result<std::unique_ptr<GrayRowReader>> OpenDecoded(const std::string& path) {
  cv::Mat gray;
  try {
    // IMREAD_COLOR + BGR2GRAY: the same gray as the streaming decoders produce.
    const cv::Mat colour = cv::imread(path, cv::IMREAD_COLOR);
    if (!colour.empty()) cv::cvtColor(colour, gray, cv::COLOR_BGR2GRAY);
  } catch (const cv::Exception& e) {
    return InvalidInput(path + ": cannot decode image (" + e.what() + ")");
  }
  if (gray.empty()) return InvalidInput(path + ": not an image format that can be decoded");
  return std::unique_ptr<GrayRowReader>(std::make_unique<DecodedRowReader>(std::move(gray)));
}

}  // namespace

Result<std::unique_ptr<GrayRowReader>> OpenGrayRowReader(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return NotFound(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) return InvalidInput(path + ": not a file");
  std::array<unsigned char, 29> head{};
  std::ifstream(path, std::ios::binary).read(reinterpret_cast<char*>(head.data()), head.size());
  static constexpr unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (std::memcmp(head.data(), kPng, 8) == 0) {
    const bool interlaced = head[28] != 0;  // IHDR interlace method byte
    return interlaced ? OpenDecoded(path) : OpenPngRowReader(path);
  }
  if (head[0] == 'P' && (head[1] == '5' || head[1] == '6')) return OpenPnmRowReader(path);
  return OpenDecoded(path);
}

}  // namespace fleetloc::mosaic
