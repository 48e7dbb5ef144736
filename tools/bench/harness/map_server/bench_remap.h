// `fleetctl bench remap`: a large streaming re-map in the map server (issue 18).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::bench {

struct RemapBenchArgs {
  int patches = 1000;
  std::string work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench-remap").string();
  std::string json;
};

// Re-maps a mosaic with `patches` stored patches in a map server child; prints its time and
// memory. The first failing step's error.
Status RunRemapBench(const RemapBenchArgs& a);

}  // namespace fleetloc::bench
