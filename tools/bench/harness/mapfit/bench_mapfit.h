// `fleetctl bench mapfit` (issues 5 and 16): the robust mean-shift map fit, the mean shift alone
// from the start (the fit before issue 16), a correspondence-free RANSAC, the nearest-landmark
// RANSAC of issue 5 (RANSAC-NN) and plain ICP on the same simulated problems of one kind
// (bench_mapfit_problems.h: `corridor` or `rooms`), per outlier level: success rate,
// wrong-converged rate, median error at the vehicle and median time per fit, side by side; one
// table for the tuning seeds and one for the held-out seeds. Progress on stderr.
#pragma once

#include <vector>

#include "base/status.h"
#include "harness/mapfit/bench_mapfit_problems.h"

namespace fleetloc::bench {

struct MapFitBenchArgs {
  int trials = 500;  // per outlier level and seed
  std::vector<unsigned> seeds{1};
  std::vector<unsigned> held_out_seeds;  // reported in a table of their own
  std::vector<double> outlier_percents;  // default per kind
  MapFitTrialOptions problems;
};

// Prints the tuning table and, with held-out seeds, theirs. InvalidInput for an unknown kind or
// too few map landmarks.
Status RunMapFitBench(MapFitBenchArgs args);

}  // namespace fleetloc::bench
