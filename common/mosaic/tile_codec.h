// Tile codec: CV_8UC1 tiles and patches ↔ PNG bytes as stored in the mosaic and sent over DDS.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <span>
#include <vector>

#include "base/status.h"

namespace fleetloc::mosaic {

// Encodes a CV_8UC1 tile as PNG with fast compression. Internal error if OpenCV fails; requires a
// non-empty CV_8UC1 tile.
Result<std::vector<std::uint8_t>> EncodeTile(const cv::Mat& tile);

// Width and height from a PNG's IHDR chunk; nullopt if `bytes` does not start like a PNG
// ((-1, -1) for absurd sizes).
std::optional<cv::Size> PngHeaderSize(std::span<const std::uint8_t> bytes);

// Ok when `bytes` start with the header of an 8-bit gray PNG of sides in [1, max_side_px]; else
// InvalidInput saying what the header declares (nothing is decoded).
Status CheckGrayPngHeader(std::span<const std::uint8_t> bytes, int max_side_px);

// Decodes an 8-bit gray PNG of any size up to max_side_px per side (size, depth and channels
// checked in the header before decoding). InvalidInput for anything else; never an exception.
Result<cv::Mat> DecodeGrayPng(std::span<const std::uint8_t> bytes, int max_side_px);

// Decodes PNG bytes into a CV_8UC1 tile of exactly tile_size_px × tile_size_px. Corrupt bytes, a
// different size or pixel type give InvalidInput (never an exception or a crash).
Result<cv::Mat> DecodeTile(std::span<const std::uint8_t> bytes, int tile_size_px);

}  // namespace fleetloc::mosaic
