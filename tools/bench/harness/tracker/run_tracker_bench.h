// `fleetctl bench tracker` as a run: resolve the floors, bench each (bench_tracker.h), print one
// table per floor, the overall table and the verdicts on stdout, every number as JSON on request.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/tracker/bench_tracker.h"

namespace fleetloc::bench {

struct TrackerBenchArgs {
  std::vector<std::string> floors;  // floor images; empty: every image in floors_dir
  std::string floors_dir;           // empty: the source tree's demo floors
  std::string work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench").string();
  std::string json;            // write every number here; empty: no JSON
  std::string tracker_config;  // fleetloc's tracker options (JSON); empty: defaults
  BenchSettings settings;
};

// Runs the benchmark. InvalidInput for an unknown or repeated method, NotFound for a missing
// floor; the first floor's or the JSON file's error otherwise.
Status RunTrackerBench(TrackerBenchArgs args);

}  // namespace fleetloc::bench
