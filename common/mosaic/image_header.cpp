// PNG IHDR, JPEG SOF, BMP and PNM header parsing.
#include "mosaic/image_header.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace fleetloc::mosaic {
namespace {

using Bytes = std::span<const std::uint8_t>;

std::uint32_t Be32(Bytes b, size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
         (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
}
std::uint32_t Be16(Bytes b, size_t at) {
  return (std::uint32_t{b[at]} << 8) | std::uint32_t{b[at + 1]};
}

std::optional<ImageHeader> Png(Bytes b) {
  static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() < 29 || !std::equal(kSignature, kSignature + 8, b.begin())) return std::nullopt;
  if (!(b[12] == 'I' && b[13] == 'H' && b[14] == 'D' && b[15] == 'R')) return std::nullopt;
  ImageHeader h;
  h.format = ImageFormat::kPng;
  h.width = Be32(b, 16);
  h.height = Be32(b, 20);
  h.bit_depth = b[24];
  switch (b[25]) {  // colour type
    case 0:
      h.channels = 1;
      break;
    case 2:
    case 3:  // palette: decodes to colour
      h.channels = 3;
      break;
    case 4:
      h.channels = 2;
      break;
    case 6:
      h.channels = 4;
      break;
    default:
      return std::nullopt;
  }
  return h;
}

std::optional<ImageHeader> Jpeg(Bytes b) {
  if (b.size() < 4 || b[0] != 0xff || b[1] != 0xd8) return std::nullopt;
  size_t at = 2;
  while (at + 4 <= b.size()) {
    if (b[at] != 0xff) return std::nullopt;
    const std::uint8_t marker = b[at + 1];
    if (marker == 0xff) {  // fill byte
      ++at;
      continue;
    }
    const std::uint32_t length = Be16(b, at + 2);
    // SOF0..SOF15 except DHT (C4), JPG (C8) and DAC (CC) carry the frame size.
    if (marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc) {
      if (at + 10 > b.size()) return std::nullopt;
      ImageHeader h;
      h.format = ImageFormat::kJpeg;
      h.bit_depth = b[at + 4];
      h.height = Be16(b, at + 5);
      h.width = Be16(b, at + 7);
      h.channels = b[at + 9];
      return h;
    }
    if (marker == 0xd9 || marker == 0xda || length < 2)
      return std::nullopt;  // no frame before the data
    at += 2 + length;
  }
  return std::nullopt;
}

// "P5"/"P6", whitespace and comments, width, height, maxval.
std::optional<ImageHeader> Pnm(Bytes b) {
  if (b.size() < 3 || b[0] != 'P' || (b[1] != '5' && b[1] != '6')) return std::nullopt;
  long long values[3] = {0, 0, 0};
  size_t at = 2;
  for (long long& value : values) {
    while (at < b.size() && (std::isspace(b[at]) || b[at] == '#')) {
      if (b[at] == '#') {
        while (at < b.size() && b[at] != '\n') ++at;
      } else {
        ++at;
      }
    }
    if (at >= b.size() || !std::isdigit(b[at])) return std::nullopt;
    for (int digits = 0; at < b.size() && std::isdigit(b[at]); ++at) {
      if (++digits > 10) return std::nullopt;
      value = value * 10 + (b[at] - '0');
    }
  }
  ImageHeader h;
  h.format = ImageFormat::kPnm;
  h.width = values[0];
  h.height = values[1];
  h.bit_depth = values[2] > 255 ? 16 : 8;
  h.channels = b[1] == '5' ? 1 : 3;
  return h;
}

// "BM", then the BITMAPINFOHEADER's width (18), height (22, negative: top-down) and bits per
// pixel (28), little-endian.
std::optional<ImageHeader> Bmp(Bytes b) {
  if (b.size() < 30 || b[0] != 'B' || b[1] != 'M') return std::nullopt;
  const auto le32 = [&](size_t at) {
    return static_cast<std::int32_t>(std::uint32_t{b[at]} | (std::uint32_t{b[at + 1]} << 8) |
                                     (std::uint32_t{b[at + 2]} << 16) |
                                     (std::uint32_t{b[at + 3]} << 24));
  };
  ImageHeader h;
  h.format = ImageFormat::kBmp;
  h.width = le32(18);
  h.height = std::abs(static_cast<long long>(le32(22)));
  const int bits = b[28] | (b[29] << 8);
  h.channels = bits >= 24 ? bits / 8 : 1;
  h.bit_depth = bits >= 24 ? 8 : bits;
  return h;
}

}  // namespace

std::string ImageHeader::Describe() const {
  return std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(bit_depth) +
         "-bit, " + std::to_string(channels) + (channels == 1 ? " channel" : " channels");
}

std::optional<ImageHeader> ReadImageHeader(std::span<const std::uint8_t> bytes) {
  if (auto h = Png(bytes)) return h;
  if (auto h = Jpeg(bytes)) return h;
  if (auto h = Bmp(bytes)) return h;
  return Pnm(bytes);
}

}  // namespace fleetloc::mosaic
