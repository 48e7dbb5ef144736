// PFNC buffer → CV_8UC1 (OpenCV does the colour and Bayer conversions).
#include "camera_io/pixel_format.h"

#include <map>
#include <opencv2/imgproc.hpp>

namespace fleetloc::camera_io {
namespace {

struct Layout {
  int type;        // OpenCV type of one buffer pixel
  int shift;       // right shift of 16-bit containers down to 8 bits
  int conversion;  // cv::cvtColor code to gray, -1: none
};

const std::map<std::string, Layout>& Layouts() {
  static const std::map<std::string, Layout> layouts = {
      {"Mono8", {CV_8UC1, 0, -1}},
      {"Mono10", {CV_16UC1, 2, -1}},
      {"Mono12", {CV_16UC1, 4, -1}},
      {"Mono16", {CV_16UC1, 8, -1}},
      {"RGB8", {CV_8UC3, 0, cv::COLOR_RGB2GRAY}},
      {"BGR8", {CV_8UC3, 0, cv::COLOR_BGR2GRAY}},
      // PFNC names the first two pixels of the top row; OpenCV names the second row's middle
      // pair, hence the apparent swap.
      {"BayerRG8", {CV_8UC1, 0, cv::COLOR_BayerBG2GRAY}},
      {"BayerGR8", {CV_8UC1, 0, cv::COLOR_BayerGB2GRAY}},
      {"BayerGB8", {CV_8UC1, 0, cv::COLOR_BayerGR2GRAY}},
      {"BayerBG8", {CV_8UC1, 0, cv::COLOR_BayerRG2GRAY}},
  };
  return layouts;
}

}  // namespace

bool IsSupportedPixelFormat(const std::string& pfnc_name) { return Layouts().contains(pfnc_name); }

Result<cv::Mat> ToGray(const void* data, size_t size, int width, int height,
                       const std::string& pfnc_name) {
  const auto it = Layouts().find(pfnc_name);
  if (it == Layouts().end()) return InvalidInput("pixel format " + pfnc_name + " is not supported");
  const Layout& layout = it->second;
  const cv::Mat view(height, width, layout.type, const_cast<void*>(data));
  const size_t needed = view.total() * view.elemSize();
  if (width <= 0 || height <= 0 || size < needed) {
    return InvalidInput("a " + pfnc_name + " buffer of " + std::to_string(size) + " bytes for " +
                        std::to_string(width) + "x" + std::to_string(height) + " (needs " +
                        std::to_string(needed) + ")");
  }
  cv::Mat gray;
  if (layout.type == CV_16UC1) {
    view.convertTo(gray, CV_8U, 1.0 / (1 << layout.shift));
  } else if (layout.conversion >= 0) {
    cv::cvtColor(view, gray, layout.conversion);
  } else {
    gray = view.clone();
  }
  return gray;
}

}  // namespace fleetloc::camera_io
