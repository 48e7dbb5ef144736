// Starts a fleetloc daemon (build/bin/<name>) as a child process for integration and fault tests
// (runtime::ChildProcess with the path filled in); aborts the test if it cannot start.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <string>
#include <vector>

#include "runtime/child_process.h"

namespace fleetloc::testing {

// The map server and the supervisor serve /metrics on a fixed port by default; here they get any
// free one unless the test names a port, so servers in one test and tests running side by side
// never contend for it (the loser would report metrics_unavailable as its health issue).
inline runtime::ChildProcess StartDaemon(const std::string& program,
                                         const std::vector<std::string>& args,
                                         const std::string& log_path,
                                         const std::vector<std::string>& env = {}) {
  std::vector<std::string> all = args;
  const bool metrics_on_by_default = program == "map_server" || program == "fleet_supervisor";
  if (metrics_on_by_default &&
      std::find(args.begin(), args.end(), "--metrics-port") == args.end()) {
    all.insert(all.end(), {"--metrics-port", "0"});
  }
  auto child = runtime::ChildProcess::Start(std::string(FLEETLOC_BINARY_DIR "/bin/") + program, all,
                                            log_path, env);
  if (!child.ok()) {
    ADD_FAILURE() << child.status().message();
    std::abort();
  }
  return std::move(child).value();
}

}  // namespace fleetloc::testing
