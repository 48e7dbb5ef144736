// `fleetctl bench mosaic` results: one table row per image size, the scaling verdict (is the
// import's peak RSS bounded, are lookups flat from the smallest to the largest size) and JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <vector>

#include "harness/mosaic/bench_mosaic.h"

namespace fleetloc::bench {

// Bounded: the import's peak RSS grows at most this much from the smallest to the largest size
// (whose pixel count is ~100× in the default sizes): memory follows the strip width, not the area.
inline constexpr double kMaxImportRssRatio = 2.0;
// Flat: each lookup's p50 at the largest size is at most this multiple of its p50 at the smallest.
inline constexpr double kMaxLookupP50Ratio = 2.0;

struct ScalingVerdict {
  bool applicable = false;  // at least two sizes
  double pixel_ratio = 0;   // largest / smallest megapixels
  double rss_ratio = 0;     // max / min import peak RSS
  bool rss_bounded = false;
  // p50 at the largest size / at the smallest: tile bytes, tile decoded, block cold, block warm.
  double tile_bytes_ratio = 0, tile_decoded_ratio = 0, block_cold_ratio = 0, block_warm_ratio = 0;
  bool lookups_flat = false;
};

// Compares the smallest and the largest size (by pixels). Requires a non-empty list.
ScalingVerdict JudgeScaling(const std::vector<MosaicSizeBench>& sizes);

void PrintMosaicTable(std::ostream& out, const std::vector<MosaicSizeBench>& sizes);
void PrintScalingVerdict(std::ostream& out, const ScalingVerdict& verdict);

nlohmann::json MosaicSizeJson(const MosaicSizeBench& size);
nlohmann::json ScalingVerdictJson(const ScalingVerdict& verdict);

}  // namespace fleetloc::bench
