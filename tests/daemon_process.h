// Starts a fleetloc daemon (build/bin/<name>) as a child process for integration and fault tests
// (io::ChildProcess with the path filled in); aborts the test if it cannot start.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>

#include <string>
#include <vector>

#include "io/child_process.h"

namespace fleetloc::testing {

inline io::ChildProcess StartDaemon(const std::string& program,
                                    const std::vector<std::string>& args,
                                    const std::string& log_path) {
  auto child = io::ChildProcess::Start(std::string(FLEETLOC_BINARY_DIR "/bin/") + program, args,
                                       log_path);
  if (!child.ok()) {
    ADD_FAILURE() << child.status().message();
    std::abort();
  }
  return std::move(child).value();
}

}  // namespace fleetloc::testing
