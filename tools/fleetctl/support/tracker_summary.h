// The JSON summary of a tracked run (frames, timing, lock, accuracy against truth), shared by
// `fleetctl track` and `fleetctl bench tracker`.
#pragma once

#include <nlohmann/json.hpp>

#include "replay/replay.h"
#include "tracking/tracker_options.h"

namespace fleetloc::fleetctl {

nlohmann::json TrackSummary(const run_io::Run& run, const replay::ReplayResult& replayed);

// `fleetctl track`'s replay: the mosaic tracker over `run` against the stored mosaic through a
// MosaicView with a `cache_mb` tile cache (defined in track_command.cpp).
Result<replay::ReplayResult> TrackOffline(const std::string& mosaic_path, const run_io::Run& run,
                                          const tracking::TrackerOptions& options,
                                          long long cache_mb);

}  // namespace fleetloc::fleetctl
