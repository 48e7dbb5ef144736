// `fleetctl bench mosaic` as a run: compose and import each size, time its lookups, print and
// write the report.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/mosaic/bench_mosaic.h"

namespace fleetloc::bench {

struct MosaicBenchArgs {
  std::vector<std::string> sizes{"3200x3200", "10240x10240", "32768x32768"};
  std::string floors_dir;
  std::string work_dir =
      (std::filesystem::temp_directory_path() / "fleetloc-bench-mosaic").string();
  std::string json;
  int tile_samples = 2000;  // in all rounds
  int block_samples = 300;  // in all rounds
  int rounds = 5;
  MosaicBenchSettings settings;
};

// Runs every size for `rounds` rounds. InvalidInput for a malformed size; the first step's
// error otherwise.
Status RunMosaicBench(MosaicBenchArgs& args);

}  // namespace fleetloc::bench
