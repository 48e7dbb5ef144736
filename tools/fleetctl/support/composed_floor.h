// A large floor image composed from blocks of real photographs (sim::FloorComposer), written as a
// binary PGM one block row at a time: `fleetctl compose-floor --size` and `fleetctl bench mosaic`.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"
#include "sim/floor_composer.h"

namespace fleetloc::fleetctl {

// Parses "WIDTHxHEIGHT" (positive integers, e.g. "32768x32768"). InvalidInput naming `option`.
Result<cv::Size> ParsePixelSize(const std::string& text, const std::string& option);

// Loads `photos` as gray, composes a floor of `options` from them and writes it to `out_pgm`
// (via `out_pgm`.partial, renamed when complete). Memory: the photos plus one block row
// (block_px × width bytes). Logs progress. InvalidInput / NotFound for unreadable photos, bad
// options or an output name not ending in .pgm; Internal on write failure.
Status ComposeFloorPgm(const std::vector<std::string>& photos,
                       const sim::FloorComposerOptions& options, const std::string& out_pgm);

}  // namespace fleetloc::fleetctl
