// `fleetctl bench patch-flood`: a map server flooded with patches (issue 18).
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "harness/tiles/bench_tiles.h"

namespace fleetloc::bench {

struct PatchFloodBenchArgs {
  TileBenchSettings tiles;  // vehicles (first entry), rate_hz, seconds, domain, work_dir
  double flood_mb_per_s = 100;
  int quota_mb = 64;
  std::string json;
};

// Floods a map server with patches while vehicles read tiles; prints the latency and the
// server's counters. The first failing step's error.
Status RunPatchFloodBench(PatchFloodBenchArgs a);

}  // namespace fleetloc::bench
