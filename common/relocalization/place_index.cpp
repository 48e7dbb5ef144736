// Building and querying the place index (see place_index.h); the blob format is in
// place_index_codec.cpp.
#include "relocalization/place_index.h"

#include <algorithm>
#include <opencv2/flann.hpp>
#include <string>

#include "geometry/pose2.h"

namespace fleetloc::relocalization {
namespace {

constexpr int kDescriptorBytes = 32;

// The level rows [y0, y1) of strip `index`, read with the feature margin above and below.
struct Strip {
  int y0 = 0, y1 = 0;
  cv::Rect read;  // level pixels
};

Strip StripAt(int index, int rows, int width, int height, int margin) {
  Strip strip;
  strip.y0 = index * rows;
  strip.y1 = std::min(height, strip.y0 + rows);
  strip.read =
      cv::Rect(-margin, strip.y0 - margin, width + 2 * margin, strip.y1 - strip.y0 + 2 * margin);
  return strip;
}

}  // namespace

Status Validate(const PlaceIndexOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options.features));
  if (options.strip_rows_px < 64) return InvalidInput("place index: strip_rows_px must be >= 64");
  if (options.lsh_tables < 1 || options.lsh_tables > 64)
    return InvalidInput("place index: lsh_tables must be 1..64");
  if (options.lsh_key_bits < 8 || options.lsh_key_bits > 30)
    return InvalidInput("place index: lsh_key_bits must be 8..30");
  if (options.lsh_multiprobe_level < 0 || options.lsh_multiprobe_level > 3)
    return InvalidInput("place index: lsh_multiprobe_level must be 0..3");
  return Status::Ok();
}

Result<PlaceIndex> PlaceIndex::Build(mosaic::RasterSource& mosaic, const PlaceIndexOptions& options,
                                     const PlaceIndexProgress& progress,
                                     const std::atomic<bool>* cancel) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  const mosaic::MosaicLayout& layout = mosaic.layout();
  const int level = options.features.level;
  if (level >= layout.levels) {
    return InvalidInput("place index: the mosaic has " + std::to_string(layout.levels) +
                        " levels, features need level " + std::to_string(level));
  }
  PlaceIndex index;
  index.options_ = options;
  index.mosaic_id_ = layout.mosaic_id;
  index.mosaic_version_ = layout.version;
  index.resolution_m_ = layout.geo.resolution;
  const geometry::Geotransform geo = layout.geo.AtLevel(level);
  const int width = layout.LevelWidth(level), height = layout.LevelHeight(level);
  const int margin = FeatureMarginPx(options.features);
  const int strips = (height + options.strip_rows_px - 1) / options.strip_rows_px;
  std::vector<cv::Mat> descriptor_blocks;
  for (int s = 0; s < strips; ++s) {
    if (cancel && cancel->load()) return Internal("place index build cancelled");
    const Strip strip = StripAt(s, options.strip_rows_px, width, height, margin);
    const cv::Mat pixels = mosaic.ReadBlock(level, strip.read);
    const cv::Rect keep(margin, margin, width, strip.y1 - strip.y0);
    FloorFeatures found = DetectFloorFeatures(pixels, pixels != 0, keep, options.features);
    for (std::size_t i = 0; i < found.size(); ++i) {
      const Eigen::Vector2d level_px =
          found.points_px[i] + Eigen::Vector2d(strip.read.x, strip.read.y);
      index.positions_m_.push_back(geo.PixelToMap(level_px));
      index.headings_rad_.push_back(geometry::WrapAngle(-found.angles_rad[i]));  // y down → up
    }
    if (!found.descriptors.empty()) descriptor_blocks.push_back(found.descriptors);
    if (progress) progress(s + 1, strips);
  }
  if (index.positions_m_.empty()) {
    return InvalidInput("place index: the mosaic has no distinctive features at level " +
                        std::to_string(level) + " (textureless or unmapped floor)");
  }
  cv::vconcat(descriptor_blocks, index.descriptors_);
  FLEETLOC_RETURN_IF_ERROR(index.Finish());
  return index;
}

Status PlaceIndex::Finish() {
  if (descriptors_.type() != CV_8UC1 || descriptors_.cols != kDescriptorBytes ||
      static_cast<std::size_t>(descriptors_.rows) != positions_m_.size() ||
      headings_rad_.size() != positions_m_.size() || positions_m_.empty()) {
    return InvalidInput("place index: inconsistent features and descriptors");
  }
  try {
    lsh_ = std::make_shared<cv::flann::Index>(
        descriptors_,
        cv::flann::LshIndexParams(options_.lsh_tables, options_.lsh_key_bits,
                                  options_.lsh_multiprobe_level),
        cvflann::FLANN_DIST_HAMMING);
  } catch (const cv::Exception& e) {
    return Internal(std::string("place index: building the LSH tables: ") + e.what());
  }
  return Status::Ok();
}

std::vector<DescriptorMatch> PlaceIndex::Match(const cv::Mat& descriptors, int k,
                                               int max_distance) const {
  std::vector<DescriptorMatch> matches;
  if (descriptors.empty()) return matches;
  FLEETLOC_CHECK(descriptors.type() == CV_8UC1 && descriptors.cols == kDescriptorBytes);
  FLEETLOC_CHECK(k >= 1);
  cv::Mat indices, distances;
  lsh_->knnSearch(descriptors, indices, distances, k, cv::flann::SearchParams());
  for (int q = 0; q < indices.rows; ++q) {
    for (int j = 0; j < k; ++j) {
      const int feature = indices.at<int>(q, j);
      const int distance = distances.at<int>(q, j);
      if (feature < 0 || feature >= static_cast<int>(size()) || distance > max_distance) continue;
      matches.push_back({q, feature, distance});
    }
  }
  return matches;
}

std::size_t PlaceIndex::MemoryBytes() const {
  return positions_m_.size() * (sizeof(Eigen::Vector2d) + sizeof(double)) +
         descriptors_.total() * descriptors_.elemSize();
}

}  // namespace fleetloc::relocalization
