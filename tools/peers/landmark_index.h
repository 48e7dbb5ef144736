// Landmark look-ups for the correspondence-free RANSAC map-fit peer (pair_ransac_map_fit.h): a
// uniform grid answering "the nearest landmark within r of this point" for scoring hypotheses,
// and the landmark pairs sorted by distance so a sampled point pair finds the landmark pairs of
// the same length by binary search. A grid and not a k-d tree: the project has no nanoflann, and
// cv::flann works in float on cv::Mat queries, a poor fit for one 2-D point at a time; with
// 30–50 landmarks and one fixed, small reach a grid is a few lines and a handful of distance
// checks per query.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

namespace fleetloc::peers {

class LandmarkGrid {
 public:
  // Cells at least `reach_m` (> 0) wide, about 16 per landmark over the landmarks' extent.
  LandmarkGrid(std::span<const Eigen::Vector2d> landmarks, double reach_m);

  // Index of the landmark nearest to `xy` if it is within reach, else -1.
  int NearestWithin(const Eigen::Vector2d& xy) const;

 private:
  std::span<const Eigen::Vector2d> landmarks_;
  double reach2_;
  Eigen::Vector2d origin_;  // lower corner of cell (0, 0)
  double cell_m_;
  int columns_, rows_;
  std::vector<int> first_;    // per cell, then one past the last: offsets into members_
  std::vector<int> members_;  // landmark indices, cell by cell
};

struct LandmarkPair {
  double distance_m;
  int a, b;  // landmark indices, a < b
};

class LandmarkPairTable {
 public:
  explicit LandmarkPairTable(std::span<const Eigen::Vector2d> landmarks);

  // The pairs whose distance is within `tolerance_m` of `distance_m`.
  std::span<const LandmarkPair> Matching(double distance_m, double tolerance_m) const;

 private:
  std::vector<LandmarkPair> pairs_;  // ascending distance
};

}  // namespace fleetloc::peers
