// The floor's own pixel-scale grain that the mosaic does not hold. A mosaic is itself made of
// camera frames, so its pixels carry that capture's noise; a live frame rendered straight from the
// mosaic pixels would share it and match them unrealistically well. FloorGrain adds a fixed,
// floor-attached noise field (the same at a floor point on every visit, independent between
// points) to the mosaic block before the camera samples it.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace fleetloc::sim {

class FloorGrain {
 public:
  // Gaussian grain of standard deviation `sigma_dn` (0: none), from one seeded 256×256 random
  // tile read with a pseudo-random circular shift per floor row and 256-pixel column block, so
  // the field does not repeat.
  FloorGrain(double sigma_dn, std::uint64_t seed);

  // Adds the grain to `block` (CV_8UC1: the level-0 mosaic pixels of `rect`), rounding and
  // saturating.
  void Apply(const cv::Rect& rect, cv::Mat* block) const;

  // The grain at level-0 mosaic pixel (x, y), in DN.
  float At(long long x, long long y) const;

 private:
  // The tile column shift used by floor row y in column block x >> kTileBits.
  int Shift(long long x, long long y) const;

  static constexpr int kTileBits = 8;
  static constexpr int kTile = 1 << kTileBits;

  double sigma_dn_;
  std::uint64_t shift_seed_;
  cv::Mat tile_;  // CV_32FC1, kTile square
};

}  // namespace fleetloc::sim
