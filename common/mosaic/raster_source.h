// RasterSource: what the tracker needs from a mosaic — its layout and coherent pixel blocks of any
// level. Implemented by MosaicView (tiles through a cache) and ImageRasterSource (an in-memory
// image, for tests and simulation). Pure: no SQLite here.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "geometry/geotransform.h"

namespace fleetloc::mosaic {

struct MosaicLayout {
  std::string mosaic_id;
  int width_px = 0;  // level 0
  int height_px = 0;
  int tile_size_px = 256;
  int levels = 1;  // level 0 .. levels-1
  geometry::Geotransform geo;
  long long version = 1;  // mosaic version (incremented by re-mapping)

  int LevelWidth(int level) const { return (width_px + (1 << level) - 1) >> level; }
  int LevelHeight(int level) const { return (height_px + (1 << level) - 1) >> level; }
};

class RasterSource {
 public:
  virtual ~RasterSource() = default;
  virtual const MosaicLayout& layout() const = 0;
  // Returns the CV_8UC1 pixels of `rect` (pixel coordinates of `level`). Pixels outside the
  // mosaic are 0. Never fails for a rect partly or wholly outside; a tile that cannot be read is
  // treated as outside and counted by the implementation.
  virtual cv::Mat ReadBlock(int level, const cv::Rect& rect) = 0;
};

// A RasterSource over an in-memory 8-bit gray image (level 0 only is exact; other levels are
// computed on demand with INTER_AREA).
class ImageRasterSource : public RasterSource {
 public:
  ImageRasterSource(cv::Mat gray, geometry::Geotransform geo);
  const MosaicLayout& layout() const override { return layout_; }
  cv::Mat ReadBlock(int level, const cv::Rect& rect) override;

 private:
  const cv::Mat& Level(int level);
  std::vector<cv::Mat> levels_;
  MosaicLayout layout_;
};

// Copies the part of `image` inside `rect` into a zero block of rect's size (shared helper).
cv::Mat CopyBlockWithZeroBorder(const cv::Mat& image, const cv::Rect& rect);

}  // namespace fleetloc::mosaic
