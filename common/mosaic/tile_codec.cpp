// PNG tile and patch encoding through OpenCV's imgcodecs; exceptions are converted to Status here.
#include "mosaic/tile_codec.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "mosaic/image_header.h"

namespace fleetloc::mosaic {

std::optional<cv::Size> PngHeaderSize(std::span<const std::uint8_t> bytes) {
  static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 24 || !std::equal(kSignature, kSignature + 8, bytes.begin())) return {};
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
  };
  const std::uint32_t width = be32(16), height = be32(20);
  if (width > (1u << 30) || height > (1u << 30)) return cv::Size(-1, -1);
  return cv::Size(static_cast<int>(width), static_cast<int>(height));
}

Result<std::vector<std::uint8_t>> EncodeTile(const cv::Mat& tile) {
  FLEETLOC_CHECK(!tile.empty() && tile.type() == CV_8UC1);
  std::vector<std::uint8_t> bytes;
  try {
    // No IMWRITE_PNG_COMPRESSION: OpenCV then takes its speed path (SUB filter, zlib level 1) and
    // the RLE strategy is named here. On real floor tiles this encodes 2.5x and decodes 1.3x
    // faster than level 1 with libpng's adaptive filters, within 1 % of its size
    // (docs/benchmarks.md, "Mosaic store at scale").
    if (cv::imencode(".png", tile, bytes,
                     {cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_RLE})) {
      return bytes;
    }
  } catch (const cv::Exception& e) {
    return Internal(std::string("tile PNG encoding failed: ") + e.what());
  }
  return Internal("tile PNG encoding failed");
}

Status CheckGrayPngHeader(std::span<const std::uint8_t> bytes, int max_side_px) {
  if (bytes.empty()) return InvalidInput("image data is empty");
  const std::optional<ImageHeader> header = ReadImageHeader(bytes);
  if (!header || header->format != ImageFormat::kPng)
    return InvalidInput("image data is not a PNG");
  if (header->width < 1 || header->height < 1 || header->width > max_side_px ||
      header->height > max_side_px) {
    return InvalidInput("image is " + std::to_string(header->width) + "x" +
                        std::to_string(header->height) + " px, sides must be in [1, " +
                        std::to_string(max_side_px) + "]");
  }
  if (header->bit_depth != 8 || header->channels != 1) {
    return InvalidInput("image is " + header->Describe() + "; it must be 8-bit gray");
  }
  return Status::Ok();
}

Result<cv::Mat> DecodeGrayPng(std::span<const std::uint8_t> bytes, int max_side_px) {
  // The header is checked before decoding, so corrupt or hostile bytes cannot make the decoder
  // allocate a huge (or deep, or colour) image.
  FLEETLOC_RETURN_IF_ERROR(CheckGrayPngHeader(bytes, max_side_px));
  const std::optional<cv::Size> size = PngHeaderSize(bytes);
  cv::Mat image;
  try {
    const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1,
                      const_cast<std::uint8_t*>(bytes.data()));
    image = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    return InvalidInput(std::string("image data is not a valid PNG: ") + e.what());
  }
  if (image.empty()) return InvalidInput("image data is not a valid PNG");
  if (image.type() != CV_8UC1) {
    return InvalidInput("image is not 8-bit single-channel (OpenCV type " +
                        std::to_string(image.type()) + ")");
  }
  if (image.size() != *size) return InvalidInput("image size differs from its PNG header");
  return image;
}

Result<cv::Mat> DecodeTile(std::span<const std::uint8_t> bytes, int tile_size_px) {
  if (bytes.empty()) return InvalidInput("tile data is empty");
  const std::optional<cv::Size> size = PngHeaderSize(bytes);
  if (size && (size->width != tile_size_px || size->height != tile_size_px)) {
    return InvalidInput("tile is " + std::to_string(size->width) + "x" +
                        std::to_string(size->height) + ", expected " +
                        std::to_string(tile_size_px) + "x" + std::to_string(tile_size_px));
  }
  Result<cv::Mat> tile = DecodeGrayPng(bytes, tile_size_px);
  if (!tile.ok()) return InvalidInput("tile: " + tile.status().message());
  return tile;
}

}  // namespace fleetloc::mosaic
