// `fleetctl bench tracker-stress` as a run: every floor x size x condition cell, one line each.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/stress/bench_stress.h"
#include "harness/tracker/bench_report.h"
#include "harness/tracker/bench_tracker.h"

namespace fleetloc::bench {

struct TrackerStressBenchArgs {
  std::string manifest;
  std::string split = "all";
  std::vector<std::string> classes;  // empty: all
  std::vector<std::string> sizes{"320x240", "640x480", "1280x1024"};
  std::vector<std::string> conditions = StressConditionNames();
  std::string work_dir = (std::filesystem::temp_directory_path() / "fleetloc-stress").string();
  std::string json;
  std::string tracker_config;
  BenchSettings settings;
};

// Issue 15's targets for fleetloc in one cell ("PASS", "MISS: what, ...", or "n/a" without a
// fleetloc row): lock ≥ 99.5 %, no false lock, camera-centre RMS ≤ 0.1 px (0.15 on plain floors)
// and below ECC's where ECC locked frames, and at 640×480 a median ≤ 2 ms (4 ms plain) and at
// most a tenth of ECC's where ECC locked frames.
std::string JudgeStressCell(const std::vector<BenchRow>& rows, const std::string& floor_class,
                            const FrameSize& size);

// Runs every cell of the manifest's floors (split, classes) x sizes x conditions. InvalidInput
// for a bad size, condition or split; the first failing cell's error otherwise.
Status RunTrackerStressBench(TrackerStressBenchArgs& args);

}  // namespace fleetloc::bench
