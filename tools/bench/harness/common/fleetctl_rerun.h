// Runs this fleetctl executable again as a child process (one benchmark step exactly as a user
// would run it) and reports its exit status, wall time and peak resident memory.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::bench {

struct RerunResult {
  int exit_code = -1;  // -1 when killed by a signal
  double wall_s = 0.0;
  double cpu_s = 0.0;            // user + system time of the child (less sensitive to load)
  long long peak_rss_bytes = 0;  // the child's own high-water mark (wait4's ru_maxrss)
};

// Runs `/proc/self/exe <args...>` with stdout and stderr sent to the given files (created or
// truncated) and waits for it. Internal when it cannot be started.
Result<RerunResult> RunFleetctlChild(const std::vector<std::string>& args,
                                     const std::filesystem::path& stdout_file,
                                     const std::filesystem::path& stderr_file);

}  // namespace fleetloc::bench
