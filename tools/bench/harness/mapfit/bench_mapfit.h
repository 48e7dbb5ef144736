// `fleetctl bench mapfit` (issues 5 and 16): the robust mean-shift map fit, the mean shift alone
// from the start (the fit before issue 16), a correspondence-free RANSAC, the nearest-landmark
// RANSAC of issue 5 (RANSAC-NN) and plain ICP on the same simulated problems of one kind (bench_mapfit_problems.h: `corridor` or `rooms`), per outlier level: success rate,
// wrong-converged rate, median error at the vehicle and median time per fit, side by side; one
// table for the tuning seeds and one for the held-out seeds. Progress on stderr.
#pragma once

#include <CLI/CLI.hpp>

#include "base/status.h"

namespace fleetloc::fleetctl {

// Adds `mapfit` to the `bench` subcommand.
void RegisterBenchMapFit(CLI::App& bench, Status* result);

}  // namespace fleetloc::fleetctl
