// PlaceIndex: a place-recognition index over a whole mosaic — distinctive floor features (ORB
// keypoints and binary descriptors, grid-bucketed so every region is covered) with their map
// positions and orientations, and a locality-sensitive hash (FLANN LSH) over the descriptors for
// fast approximate nearest-neighbour matching. Built by the map server from its mosaic in strips
// (bounded memory), stored and streamed as a versioned byte blob. Pure: no files, SQLite or DDS.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <span>
#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/raster_source.h"
#include "relocalization/floor_features.h"

namespace cv::flann {
class Index;
}

namespace fleetloc::relocalization {

struct PlaceIndexOptions {
  FloorFeatureOptions features;
  int strip_rows_px = 512;  // level rows detected per strip while building (bounds memory)
  // LSH: measured on the 108 Mpx bench mosaic (156k features), 12 tables of 20-bit keys without
  // multi-probing match a frame in ~8 ms with every trial still correct; multi-probe level 2
  // (8 × 20 bits) took ~330 ms for no gain.
  int lsh_tables = 12;           // LSH hash tables
  int lsh_key_bits = 20;         // bits of each table's key
  int lsh_multiprobe_level = 0;  // neighbouring buckets probed (bits flipped)
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const PlaceIndexOptions& options);

// One candidate correspondence of a query descriptor: an index feature and the Hamming distance.
struct DescriptorMatch {
  int query = 0;
  int feature = 0;
  int distance = 0;
};

// Called with strips done and the total while building.
using PlaceIndexProgress = std::function<void(int strips_done, int strips_total)>;

class PlaceIndex {
 public:
  // Detects features over the whole mosaic at options.features.level, strip by strip (memory: one
  // strip of the level plus the features). Unmapped mosaic pixels (0) yield no features.
  // InvalidInput for bad options, a level the mosaic lacks, or a floor without any distinctive
  // feature (e.g. textureless); Internal "cancelled" when *cancel becomes true (checked per strip).
  static Result<PlaceIndex> Build(mosaic::RasterSource& mosaic, const PlaceIndexOptions& options,
                                  const PlaceIndexProgress& progress = {},
                                  const std::atomic<bool>* cancel = nullptr);

  // A blob from Serialize(). InvalidInput naming the problem (not an index, unknown version,
  // truncated, checksum mismatch, inconsistent fields) — never a crash.
  static Result<PlaceIndex> Deserialize(std::span<const std::uint8_t> blob);
  std::vector<std::uint8_t> Serialize() const;

  // Up to `k` nearest index features (approximate) of each row of `descriptors` (CV_8UC1, 32
  // bytes a row) with Hamming distance <= max_distance, best first per query.
  std::vector<DescriptorMatch> Match(const cv::Mat& descriptors, int k, int max_distance) const;

  const PlaceIndexOptions& options() const { return options_; }
  const std::string& mosaic_id() const { return mosaic_id_; }
  long long mosaic_version() const { return mosaic_version_; }
  double resolution_m() const { return resolution_m_; }  // level 0 of the mosaic
  std::size_t size() const { return positions_m_.size(); }
  const Eigen::Vector2d& position_m(int feature) const { return positions_m_[feature]; }
  double heading_rad(int feature) const { return headings_rad_[feature]; }  // in map, CCW from +x
  const cv::Mat& descriptors() const { return descriptors_; }
  std::size_t MemoryBytes() const;  // features and descriptors (the LSH tables excluded)

 private:
  PlaceIndex() = default;
  // Checks the features and builds the LSH tables over the descriptors.
  Status Finish();

  PlaceIndexOptions options_;
  std::string mosaic_id_;
  long long mosaic_version_ = 0;
  double resolution_m_ = 0.0;
  std::vector<Eigen::Vector2d> positions_m_;
  std::vector<double> headings_rad_;
  cv::Mat descriptors_;
  std::shared_ptr<cv::flann::Index> lsh_;  // reads descriptors_ (never reallocated once built)

  friend class PlaceIndexCodec;
};

}  // namespace fleetloc::relocalization
