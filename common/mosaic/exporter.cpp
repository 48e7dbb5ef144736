// Level export: blocks from a RasterSource into a PNG row writer or cv::imwrite.
#include "mosaic/exporter.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "mosaic/row_image_io.h"

namespace fleetloc::mosaic {
namespace {

constexpr double kEdgeTolerancePx = 1e-6;
constexpr int kMaxExportSizePx = 1 << 24;

bool IsPng(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

Result<cv::Rect> CheckedRect(const MosaicLayout& layout, int level,
                             const std::optional<MapRegion>& region) {
  if (level < 0 || level >= layout.levels) {
    return InvalidInput("--level " + std::to_string(level) + " is outside the pyramid (levels 0.." +
                        std::to_string(layout.levels - 1) + ")");
  }
  const cv::Rect bounds(0, 0, layout.LevelWidth(level), layout.LevelHeight(level));
  if (!region) return bounds;
  const MapRegion& r = *region;
  if (!std::isfinite(r.x0_m) || !std::isfinite(r.y0_m) || !std::isfinite(r.x1_m) ||
      !std::isfinite(r.y1_m)) {
    return InvalidInput("--region must be four finite numbers x0,y0,x1,y1");
  }
  const double max_px =
      static_cast<double>(kMaxExportSizePx) * layout.geo.AtLevel(level).resolution;
  if (std::abs(r.x1_m - r.x0_m) > max_px || std::abs(r.y1_m - r.y0_m) > max_px) {
    return InvalidInput("--region is larger than 2^24 pixels at this level");
  }
  const cv::Rect rect = RegionToPixelRect(layout, level, r);
  if (rect.empty()) return InvalidInput("--region is empty");
  if ((rect & bounds).empty()) return InvalidInput("--region does not overlap the mosaic");
  return rect;
}

Status WritePngStrips(RasterSource& source, int level, const cv::Rect& rect,
                      const std::string& out_path) {
  Result<std::unique_ptr<GrayRowWriter>> writer =
      CreatePngRowWriter(out_path, rect.width, rect.height);
  if (!writer.ok()) return writer.status();
  const int strip_rows = source.layout().tile_size_px;
  for (int y = rect.y; y < rect.y + rect.height; y += strip_rows) {
    const int rows = std::min(strip_rows, rect.y + rect.height - y);
    const cv::Mat strip = source.ReadBlock(level, cv::Rect(rect.x, y, rect.width, rows));
    for (int i = 0; i < rows; ++i) {
      FLEETLOC_RETURN_IF_ERROR(
          (*writer)->WriteRow({strip.ptr(i), static_cast<std::size_t>(rect.width)}));
    }
  }
  return (*writer)->Finish();
}

Status WriteWhole(RasterSource& source, int level, const cv::Rect& rect,
                  const std::string& out_path) {
  try {
    if (cv::imwrite(out_path, source.ReadBlock(level, rect))) return Status::Ok();
  } catch (const cv::Exception& e) {
    return Internal(out_path + ": cannot write image (" + e.what() + ")");
  }
  return Internal(out_path + ": cannot write image");
}

}  // namespace

cv::Rect RegionToPixelRect(const MosaicLayout& layout, int level, const MapRegion& region) {
  FLEETLOC_CHECK(level >= 0 && level < layout.levels);
  const geometry::Geotransform geo = layout.geo.AtLevel(level);
  const Eigen::Vector2d a = geo.MapToPixel({region.x0_m, region.y0_m});
  const Eigen::Vector2d b = geo.MapToPixel({region.x1_m, region.y1_m});
  // Clamped so that far-away regions stay representable (they then miss the mosaic).
  const auto to_int = [](double px) { return static_cast<int>(std::clamp(px, -1e9, 1e9)); };
  const int u0 = to_int(std::floor(std::min(a.x(), b.x()) + kEdgeTolerancePx));
  const int v0 = to_int(std::floor(std::min(a.y(), b.y()) + kEdgeTolerancePx));
  const int u1 = to_int(std::ceil(std::max(a.x(), b.x()) - kEdgeTolerancePx));
  const int v1 = to_int(std::ceil(std::max(a.y(), b.y()) - kEdgeTolerancePx));
  return {u0, v0, std::max(0, u1 - u0), std::max(0, v1 - v0)};
}

Result<cv::Rect> ExportImage(RasterSource& source, int level,
                             const std::optional<MapRegion>& region, const std::string& out_path) {
  Result<cv::Rect> rect = CheckedRect(source.layout(), level, region);
  if (!rect.ok()) return rect.status();
  std::error_code ec;
  if (!std::filesystem::is_directory(std::filesystem::absolute(out_path, ec).parent_path(), ec)) {
    return InvalidInput(out_path + ": the directory does not exist");
  }
  const bool png = IsPng(out_path);
  if (!png && !cv::haveImageWriter(out_path)) {
    return InvalidInput(out_path + ": unknown image format (use .png, .jpg, .tif, ...)");
  }
  const Status written = png ? WritePngStrips(source, level, *rect, out_path)
                             : WriteWhole(source, level, *rect, out_path);
  if (!written.ok()) {
    std::filesystem::remove(out_path, ec);
    return written;
  }
  return rect;
}

}  // namespace fleetloc::mosaic
