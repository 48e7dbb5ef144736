// `fleetctl bench supervisor`: the fleet supervisor under a simulated fleet.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::bench {

struct SupervisorBenchArgs {
  int vehicles = 500;
  double pose_hz = 30;
  double seconds = 20;
  int domain = 102;
  std::string work_dir =
      (std::filesystem::temp_directory_path() / "fleetloc-bench-supervisor").string();
  std::string json;
  std::string supervisor_config;  // passed to the supervisor as --config (e.g. VDA 5050 on)
};

// Starts a supervisor child, publishes the simulated fleet and reads its stream; prints the
// backlog, stream latency, CPU and memory. The first failing step's error.
Status RunSupervisorBench(const SupervisorBenchArgs& a);

}  // namespace fleetloc::bench
