// `fleetctl bench mosaic-build` (issue 3): a slow, overlapping mapping run simulated over a real
// floor photo, `fleetctl mosaic build` on it (wall time and peak RSS of that process alone), the
// built mosaic's local distortion against the true photo, and a fast run tracked against the built
// mosaic and, for reference, against the photo imported directly. Each step runs as its own
// fleetctl process, exactly as a user would run it.
#pragma once

#include <filesystem>
#include <string>

#include "base/status.h"

namespace fleetloc::bench {

struct MosaicBuildBenchArgs {
  std::string floor;  // default: rock_dirt_2048.png of the demo floors
  double resolution_m = 0.0005;
  int mapping_frames = 160;  // a little more than one lap of the figure eight at 300 px/s
  double mapping_speed_px_s = 300.0;
  int fast_frames = 200;
  double rate_hz = 5.0;
  int seed = 11;  // the fast run uses seed + 1
  std::string work_dir =
      (std::filesystem::temp_directory_path() / "fleetloc-bench-mosaic-build").string();
  std::string json;
};

// Runs the steps as fleetctl children and prints the report. The first failing step's error.
Status RunMosaicBuildBench(MosaicBuildBenchArgs s);

}  // namespace fleetloc::bench
