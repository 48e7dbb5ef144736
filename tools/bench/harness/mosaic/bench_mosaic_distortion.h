// `fleetctl bench mosaic-distortion` and the measurement behind it: a built mosaic's local
// distortion against the true floor image it was mapped from (see mapping/mosaic_distortion.h).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "base/status.h"
#include "mapping/mosaic_distortion.h"

namespace fleetloc::bench {

// The distortion of the mosaic in `built_db` against `truth_image` placed as `fleetctl sim
// --image` places it (top-left corner at map (0, height · resolution)): the built mosaic's level 0
// is read over the truth's extent (the two pixel grids must coincide) and measured patch by
// patch. NotFound / InvalidInput naming the file for unreadable input or misaligned grids.
Result<mapping::DistortionReport> MeasureBuiltMosaicDistortion(
    const std::filesystem::path& built_db, const std::filesystem::path& truth_image,
    double resolution_m);

// Every number of a report but the per-patch list.
nlohmann::json DistortionJson(const mapping::DistortionReport& report);

struct MosaicDistortionBenchArgs {
  std::string mosaic;
  std::string truth;
  double resolution_m = 0.0005;
};

// The measurement alone, as JSON on stdout. The measurement's error on failure.
Status RunMosaicDistortionBench(const MosaicDistortionBenchArgs& args);

}  // namespace fleetloc::bench
