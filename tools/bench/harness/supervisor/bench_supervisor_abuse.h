// `fleetctl bench supervisor-abuse`: the fleet supervisor under hostile HTTP clients.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/supervisor/http_abuse.h"

namespace fleetloc::bench {

struct SupervisorAbuseBenchArgs {
  AbuseOptions abuse;
  double seconds = 20;      // measured under attack (after a 2 s ramp)
  double idle_seconds = 5;  // measured before the attack
  double requests_hz = 5;   // operator requests per second (each: one GET, one POST)
  int domain = 104;
  std::string work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench-abuse").string();
  std::string json;
};

// Measures operator requests to a supervisor child idle, then under the hostile clients.
// The first failing step's error.
Status RunSupervisorAbuseBench(SupervisorAbuseBenchArgs a);

}  // namespace fleetloc::bench
