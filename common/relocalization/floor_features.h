// Distinctive floor features for place recognition: ORB keypoints (FAST corners with an intensity
// centroid orientation) and their 256-bit rBRIEF descriptors, kept evenly spread by a grid of
// buckets so every region of the floor is covered. The same detector runs on mosaic strips (the
// place index) and on camera frames (the relocalizer), at the same pyramid level. OpenCV's ORB is
// used rather than hand-written code: it is rotation invariant, binary (Hamming matching, LSH
// indexing) and fast enough for a 100-megapixel mosaic in seconds.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "base/status.h"

namespace fleetloc::relocalization {

struct FloorFeatureOptions {
  int level = 1;               // pyramid level features are detected at (0: full resolution)
  int cell_px = 32;            // bucket side, level pixels
  int features_per_cell = 6;   // strongest features kept per bucket
  int fast_threshold = 12;     // FAST intensity threshold (grey levels)
  int patch_size_px = 31;      // ORB descriptor patch side (level pixels), odd, >= 15
  double blur_sigma_px = 0.0;  // Gaussian blur of the level image before detection; 0 = none
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const FloorFeatureOptions& options);

struct FloorFeatures {
  std::vector<Eigen::Vector2d> points_px;  // continuous level-pixel coordinates (centre i + 0.5)
  std::vector<double> angles_rad;          // orientation in image axes (x right, y down)
  std::vector<float> responses;
  cv::Mat descriptors;  // CV_8UC1, one 32-byte row per feature
  std::size_t size() const { return points_px.size(); }
};

// Detects features in `image` (CV_8UC1 at the options' level). Only pixels where `valid` (CV_8UC1,
// same size, non-zero = usable; empty = all) holds, farther than the descriptor's reach from
// invalid pixels and the border, yield features; only features whose point lies in `keep`
// (level pixels of `image`) are returned, at most features_per_cell per bucket of a grid anchored
// at keep's top-left corner. Options must have passed Validate().
FloorFeatures DetectFloorFeatures(const cv::Mat& image, const cv::Mat& valid, const cv::Rect& keep,
                                  const FloorFeatureOptions& options);

// Margin (level pixels) a strip needs around the rows it keeps so its features equal the whole
// image's: the descriptor patch's reach plus the blur's.
int FeatureMarginPx(const FloorFeatureOptions& options);

}  // namespace fleetloc::relocalization
