// Export of (part of) one pyramid level to an image file (`fleetctl mosaic export`).
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "base/status.h"
#include "mosaic/raster_source.h"

namespace fleetloc::mosaic {

// An axis-aligned map region given by two opposite corners, metres (docs/cli.md, mosaic export
// --region: x0,y0,x1,y1).
struct MapRegion {
  double x0_m = 0, y0_m = 0, x1_m = 0, y1_m = 0;
};

// The pixel rectangle of `level` that covers `region` (rounded outwards; a corner within 1e-6 px
// of a pixel edge counts as on it). Requires a valid level.
cv::Rect RegionToPixelRect(const MosaicLayout& layout, int level, const MapRegion& region);

// Renders `region` (default: the whole level) of `level` as an 8-bit gray image at `out_path`;
// pixels outside the mosaic are black. PNG is written strip by strip (memory about one strip of
// tile_size rows); other formats known to OpenCV (by extension) are rendered whole. Returns the
// pixel rectangle written. InvalidInput for a level outside the pyramid, an empty, non-finite or
// non-overlapping region, or an unknown output format; Internal on write failure (then no file is
// left behind).
Result<cv::Rect> ExportImage(RasterSource& source, int level,
                             const std::optional<MapRegion>& region, const std::string& out_path);

}  // namespace fleetloc::mosaic
