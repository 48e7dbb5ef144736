// `fleetctl bench mosaic-build` (issue 3): a slow, overlapping mapping run simulated over a real
// floor photo, `fleetctl mosaic build` on it (wall time and peak RSS of that process alone), the
// built mosaic's local distortion against the true photo, and a fast run tracked against the built
// mosaic and, for reference, against the photo imported directly. Each step runs as its own
// fleetctl process, exactly as a user would run it.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>

#include "base/status.h"
#include "mapping/mosaic_distortion.h"

namespace fleetloc::fleetctl {

// Adds `mosaic-build` and `mosaic-distortion` (the distortion measurement alone, as JSON) to the
// `bench` subcommand.
void RegisterBenchMosaicBuild(CLI::App& bench, Status* result);

// The distortion of the mosaic in `built_db` against `truth_image` placed as `fleetctl sim
// --image` places it (top-left corner at map (0, height · resolution)): the built mosaic's level 0
// is read over the truth's extent (the two pixel grids must coincide) and measured patch by
// patch. NotFound / InvalidInput naming the file for unreadable input or misaligned grids.
Result<mapping::DistortionReport> MeasureBuiltMosaicDistortion(
    const std::filesystem::path& built_db, const std::filesystem::path& truth_image,
    double resolution_m);

}  // namespace fleetloc::fleetctl
