// Camera buffers in GenICam pixel formats (PFNC names) to the 8-bit gray image the tracker reads.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "base/status.h"

namespace fleetloc::camera_io {

// True for the formats ToGray converts: Mono8, Mono10/12/16 (little-endian 16-bit containers),
// RGB8, BGR8 and the 8-bit Bayer patterns (BayerRG8, BayerGR8, BayerGB8, BayerBG8).
bool IsSupportedPixelFormat(const std::string& pfnc_name);

// A copy of the `width`×`height` buffer as CV_8UC1. InvalidInput naming the format when it is
// not supported or `size` is smaller than the image needs.
Result<cv::Mat> ToGray(const void* data, size_t size, int width, int height,
                       const std::string& pfnc_name);

}  // namespace fleetloc::camera_io
