// Poisson draws and per-cell seeds of the procedural floor items.
#include "sim/cell_field.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>

namespace fleetloc::sim {

int PoissonDraw(double mean, cv::RNG& rng) {
  if (mean > 50.0)
    return std::max(0, static_cast<int>(std::lround(mean + rng.gaussian(std::sqrt(mean)))));
  const double limit = std::exp(-mean);
  int k = 0;
  for (double p = rng.uniform(0.0, 1.0); p > limit; p *= rng.uniform(0.0, 1.0)) ++k;
  return k;
}

std::uint64_t CellSeed(std::uint64_t seed, std::uint64_t stream, long long ix, long long iy) {
  return MixSeed(MixSeed(seed, stream),
                 SplitMix64(static_cast<std::uint64_t>(ix)) ^ static_cast<std::uint64_t>(iy));
}

Affine2 InvertAffine(const Affine2& a) {
  const Eigen::Matrix2d inverse = a.leftCols<2>().inverse();
  Affine2 out;
  out.leftCols<2>() = inverse;
  out.col(2) = -inverse * a.col(2);
  return out;
}

void ImageFootprint(const Affine2& pixel_to_map, cv::Size size, Eigen::Vector2d* lo,
                    Eigen::Vector2d* hi) {
  *lo = Eigen::Vector2d(INFINITY, INFINITY);
  *hi = -*lo;
  for (const Eigen::Vector2d& uv :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(size.width, 0), Eigen::Vector2d(0, size.height),
        Eigen::Vector2d(size.width, size.height)}) {
    const Eigen::Vector2d xy = pixel_to_map * uv.homogeneous();
    *lo = lo->cwiseMin(xy);
    *hi = hi->cwiseMax(xy);
  }
}

double CoveredShare(const cv::Mat& covered, const cv::Rect& count_region) {
  const cv::Rect region = count_region & cv::Rect(0, 0, covered.cols, covered.rows);
  if (region.area() == 0) return 0.0;
  return static_cast<double>(cv::countNonZero(covered(region))) / region.area();
}

}  // namespace fleetloc::sim
