// Floor grain: a random tile read with per-row, per-block pseudo-random shifts.
#include "sim/floor_grain.h"

#include <algorithm>

#include "sim/random.h"

namespace fleetloc::sim {
namespace {

constexpr std::uint64_t kGrainStream = 0x6772616e;  // "gran"

}  // namespace

FloorGrain::FloorGrain(double sigma_dn, std::uint64_t seed)
    : sigma_dn_(sigma_dn), shift_seed_(MixSeed(seed, kGrainStream + 1)) {
  if (sigma_dn <= 0) return;
  cv::RNG rng(MixSeed(seed, kGrainStream));
  tile_.create(kTile, kTile, CV_32FC1);
  rng.fill(tile_, cv::RNG::NORMAL, 0.0, sigma_dn);
}

int FloorGrain::Shift(long long x, long long y) const {
  const std::uint64_t block = static_cast<std::uint64_t>(x >> kTileBits);
  return static_cast<int>(SplitMix64(shift_seed_ ^ SplitMix64(block) ^
                                     (SplitMix64(static_cast<std::uint64_t>(y)) >> 1)) &
                          (kTile - 1));
}

float FloorGrain::At(long long x, long long y) const {
  if (sigma_dn_ <= 0) return 0.0f;
  return tile_.at<float>(static_cast<int>(y & (kTile - 1)),
                         static_cast<int>((x + Shift(x, y)) & (kTile - 1)));
}

void FloorGrain::Apply(const cv::Rect& rect, cv::Mat* block) const {
  CV_Assert(block->type() == CV_8UC1 && block->size() == rect.size());
  if (sigma_dn_ <= 0) return;
  for (int j = 0; j < rect.height; ++j) {
    const long long y = static_cast<long long>(rect.y) + j;
    const float* tile_row = tile_.ptr<float>(static_cast<int>(y & (kTile - 1)));
    std::uint8_t* row = block->ptr<std::uint8_t>(j);
    // Walk the row one 256-pixel column block at a time (one shift each).
    for (int i = 0; i < rect.width;) {
      const long long x = static_cast<long long>(rect.x) + i;
      const int in_block = std::min<long long>(rect.width - i, kTile - (x & (kTile - 1)));
      int column = static_cast<int>((x + Shift(x, y)) & (kTile - 1));
      for (int k = 0; k < in_block; ++k, ++i) {
        row[i] = cv::saturate_cast<std::uint8_t>(row[i] + tile_row[column]);
        column = (column + 1) & (kTile - 1);
      }
    }
  }
}

}  // namespace fleetloc::sim
