// `fleetctl bench mapfit` (issue 5): the mean-shift map fit against RANSAC and plain ICP on the
// same simulated problems — a corridor landmark map, points around the landmarks near the vehicle
// with centimetre noise, 50–90 % uniform outliers, a start a few centimetres and degrees off.
// Success rate, median error and time per fit, side by side; progress on stderr.
#pragma once

#include <CLI/CLI.hpp>

#include "base/status.h"

namespace fleetloc::fleetctl {

// Adds `mapfit` to the `bench` subcommand.
void RegisterBenchMapFit(CLI::App& bench, Status* result);

}  // namespace fleetloc::fleetctl
