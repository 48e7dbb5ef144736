// ImageRasterSource and block copying.
#include "mosaic/raster_source.h"

#include <opencv2/imgproc.hpp>

#include "mosaic/tile_key.h"

namespace fleetloc::mosaic {

cv::Mat CopyBlockWithZeroBorder(const cv::Mat& image, const cv::Rect& rect) {
  cv::Mat block = cv::Mat::zeros(rect.size(), image.type());
  const cv::Rect inside = rect & cv::Rect(0, 0, image.cols, image.rows);
  if (inside.area() > 0) image(inside).copyTo(block(inside - rect.tl()));
  return block;
}

ImageRasterSource::ImageRasterSource(cv::Mat gray, geometry::Geotransform geo) {
  CV_Assert(gray.type() == CV_8UC1);
  layout_.mosaic_id = "in-memory";
  layout_.width_px = gray.cols;
  layout_.height_px = gray.rows;
  layout_.geo = geo;
  layout_.levels = PyramidLevelCount(gray.cols, gray.rows, layout_.tile_size_px);
  levels_.push_back(std::move(gray));
}

const cv::Mat& ImageRasterSource::Level(int level) {
  while (static_cast<int>(levels_.size()) <= level) {
    const int k = static_cast<int>(levels_.size());
    cv::Mat next;
    cv::resize(levels_.back(), next, cv::Size(layout_.LevelWidth(k), layout_.LevelHeight(k)), 0, 0,
               cv::INTER_AREA);
    levels_.push_back(next);
  }
  return levels_[level];
}

cv::Mat ImageRasterSource::ReadBlock(int level, const cv::Rect& rect) {
  return CopyBlockWithZeroBorder(Level(level), rect);
}

}  // namespace fleetloc::mosaic
