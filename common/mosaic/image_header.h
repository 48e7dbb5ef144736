// What an encoded image says about itself before it is decoded: format, size, bit depth and
// channels, read from the first bytes (PNG IHDR, JPEG SOF, BMP, binary PNM). Decoders check these
// against their limits first, so a small file declaring a huge, deep or colour image is refused
// without the decoder allocating anything. Pure: bytes in, a header out.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace fleetloc::mosaic {

enum class ImageFormat { kPng, kJpeg, kBmp, kPnm };

struct ImageHeader {
  ImageFormat format = ImageFormat::kPng;
  long long width = 0, height = 0;
  int bit_depth = 8;  // bits per channel
  int channels = 1;   // 1 gray, 2 gray + alpha, 3 colour, 4 colour + alpha (PNG palette: 3)
  long long pixels() const { return width * height; }
  // "640x480, 8-bit, 1 channel".
  std::string Describe() const;
};

// The header of a PNG, JPEG, BMP or binary PNM (P5, P6) image from its first bytes (a JPEG's SOF
// may come after its EXIF block: pass up to 256 KiB). nullopt when the bytes are not one of these
// or too short to tell.
std::optional<ImageHeader> ReadImageHeader(std::span<const std::uint8_t> bytes);

}  // namespace fleetloc::mosaic
