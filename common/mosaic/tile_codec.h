// Tile codec: CV_8UC1 tiles ↔ PNG bytes as stored in the tile store and sent over DDS.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

#include "base/status.h"

namespace fleetloc::mosaic {

// Encodes a CV_8UC1 tile as PNG with fast compression. Internal error if OpenCV fails; requires a
// non-empty CV_8UC1 tile.
Result<std::vector<std::uint8_t>> EncodeTile(const cv::Mat& tile);

// Decodes PNG bytes into a CV_8UC1 tile of exactly tile_size_px × tile_size_px. Corrupt bytes, a
// different size or pixel type give InvalidInput (never an exception or a crash).
Result<cv::Mat> DecodeTile(std::span<const std::uint8_t> bytes, int tile_size_px);

}  // namespace fleetloc::mosaic
