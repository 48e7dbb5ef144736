// `fleetctl bench mosaic-build` (issue 3): a slow, overlapping mapping run simulated over a real
// floor photo, `fleetctl mosaic build` on it (wall time and peak RSS of that process alone), the
// built mosaic's local distortion against the true photo, and a fast run tracked against the built
// mosaic and, for reference, against the photo imported directly. Each step runs as its own
// fleetctl process, exactly as a user would run it.
#pragma once

#include <CLI/CLI.hpp>

#include "base/status.h"

namespace fleetloc::fleetctl {

// Adds `mosaic-build` to the `bench` subcommand.
void RegisterBenchMosaicBuild(CLI::App& bench, Status* result);

}  // namespace fleetloc::fleetctl
