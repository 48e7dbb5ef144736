// `fleetctl bench reloc` as a run: one floor's mosaic, its place index built in a child, the
// relocalization trials.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/reloc/bench_reloc.h"
#include "harness/reloc/bench_reloc_stress.h"
#include "relocalization/place_index.h"

namespace fleetloc::bench {

struct RelocBenchArgs {
  std::string mosaic;  // use this mosaic instead of composing one
  std::string size = "12000x9000";
  std::string floors_dir;
  std::string work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench-reloc").string();
  std::string json;
  relocalization::PlaceIndexOptions index;
  RelocTrialSettings trials;
  bool stress = false;       // the stress floors instead (bench_reloc_stress.h)
  RelocStressArgs stressed;  // its floors, sizes, conditions and layouts
};

// The trials on one mosaic (composed when none is given), or with `stress` the stress floors.
// The first failing step's error.
Status RunRelocBench(const RelocBenchArgs& args);

}  // namespace fleetloc::bench
