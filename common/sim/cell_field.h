// Procedural items scattered over the floor by map cell: a Poisson number of items per square
// cell, each cell drawn from its own seed, so every visit to a spot sees the same items and any
// floor size costs no memory. Floor dust and floor marks (tyre marks, debris) both use it.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "sim/random.h"

namespace fleetloc::sim {

// A Poisson draw of mean `mean` (normal approximation above 50).
int PoissonDraw(double mean, cv::RNG& rng);

// The seed of cell (ix, iy) of stream `stream` of run seed `seed`.
std::uint64_t CellSeed(std::uint64_t seed, std::uint64_t stream, long long ix, long long iy);

using Affine2 = Eigen::Matrix<double, 2, 3>;

// The inverse of an invertible 2-D affine map.
Affine2 InvertAffine(const Affine2& a);

// The axis-aligned map box [lo, hi] that an image of `size` covers, its continuous pixel (u, v)
// lying at pixel_to_map · (u, v, 1).
void ImageFootprint(const Affine2& pixel_to_map, cv::Size size, Eigen::Vector2d* lo,
                    Eigen::Vector2d* hi);

// The share of `count_region`'s pixels that are non-zero in the CV_8UC1 `covered`.
double CoveredShare(const cv::Mat& covered, const cv::Rect& count_region);

// The items whose `centre_m` lies in the map box [lo, hi], from every cell that box touches, in
// a fixed order. `draw(rng, cell_origin_m)` draws one item of the cell; each cell holds
// PoissonDraw(mean_per_cell) items.
template <typename Item, typename Draw>
std::vector<Item> ItemsInBox(std::uint64_t seed, std::uint64_t stream, double cell_m,
                             double mean_per_cell, const Eigen::Vector2d& lo,
                             const Eigen::Vector2d& hi, const Draw& draw) {
  std::vector<Item> items;
  if (mean_per_cell <= 0) return items;
  for (auto iy = static_cast<long long>(std::floor(lo.y() / cell_m));
       iy <= static_cast<long long>(std::floor(hi.y() / cell_m)); ++iy) {
    for (auto ix = static_cast<long long>(std::floor(lo.x() / cell_m));
         ix <= static_cast<long long>(std::floor(hi.x() / cell_m)); ++ix) {
      cv::RNG rng(CellSeed(seed, stream, ix, iy));
      const Eigen::Vector2d origin(ix * cell_m, iy * cell_m);
      for (int n = PoissonDraw(mean_per_cell, rng); n > 0; --n) {
        Item item = draw(rng, origin);
        if ((item.centre_m.array() >= lo.array()).all() &&
            (item.centre_m.array() <= hi.array()).all()) {
          items.push_back(std::move(item));
        }
      }
    }
  }
  return items;
}

}  // namespace fleetloc::sim
