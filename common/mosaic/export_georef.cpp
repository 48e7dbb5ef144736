// World file and Nav2 map.yaml text.
#include "mosaic/export_georef.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace fleetloc::mosaic {

namespace {

// Shortest text that reads back as exactly `v`.
std::string Number(double v) {
  char text[32];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

}  // namespace

std::string WorldFilePath(const std::string& image_path) {
  std::filesystem::path path(image_path);
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") return path.replace_extension(".pgw").string();
  if (ext == ".jpg" || ext == ".jpeg") return path.replace_extension(".jgw").string();
  if (ext == ".tif" || ext == ".tiff") return path.replace_extension(".tfw").string();
  return image_path + "w";
}

std::string WorldFileText(const MosaicLayout& layout, int level, const cv::Rect& rect) {
  const double res = layout.geo.resolution * std::ldexp(1.0, level);
  const double x = layout.geo.origin_x + (rect.x + 0.5) * res;
  const double y = layout.geo.origin_y - (rect.y + 0.5) * res;
  return Number(res) + "\n0\n0\n" + Number(-res) + "\n" + Number(x) + "\n" + Number(y) + "\n";
}

std::string Nav2MapYaml(const MosaicLayout& layout, int level, const cv::Rect& rect,
                        const std::string& image) {
  const double res = layout.geo.resolution * std::ldexp(1.0, level);
  const double x = layout.geo.origin_x + rect.x * res;
  const double y = layout.geo.origin_y - (rect.y + rect.height) * res;
  return "# fleetloc mosaic " + layout.mosaic_id + " version " + std::to_string(layout.version) +
         ", level " + std::to_string(level) + "\nimage: " + image +
         "\nmode: raw\nresolution: " + Number(res) + "\norigin: [" + Number(x) + ", " + Number(y) +
         ", 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
}

}  // namespace fleetloc::mosaic
