// The JSON summary of a tracked run (frames, timing, lock, accuracy against truth), shared by
// `fleetctl track` and `fleetctl bench tracker`.
#pragma once

#include <nlohmann/json.hpp>

#include "replay/replay.h"

namespace fleetloc::fleetctl {

nlohmann::json TrackSummary(const io::Run& run, const replay::ReplayResult& replayed);

}  // namespace fleetloc::fleetctl
