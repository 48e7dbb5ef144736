// Runs one step of a benchmark in a forked child process and reports what the child used (wall and
// CPU time, peak resident set), so each step's memory is measured apart from the caller's.
#pragma once

#include <functional>
#include <string>

#include "base/status.h"

namespace fleetloc::bench {

struct ChildRun {
  std::string output;  // what the work returned
  double wall_s = 0, user_s = 0, system_s = 0;
  // The child's ru_maxrss. A forked child starts as a copy of the caller, so this includes the
  // caller's resident anonymous memory at the fork: keep the caller small (see ResidentBytes).
  long long peak_rss_bytes = 0;
};

// Forks; the child runs `work` and hands its result back through a pipe. Returns the output and
// usage when the work succeeded; the work's own Status (code and message) when it failed; Internal
// if the fork fails or the child dies without reporting (e.g. killed by a signal). The caller must
// be single-threaded (only the forking thread exists in the child).
Result<ChildRun> RunInChild(const std::function<Result<std::string>()>& work);

// The calling process's resident set now (VmRSS), bytes; 0 if /proc cannot tell.
long long ResidentBytes();

}  // namespace fleetloc::bench
