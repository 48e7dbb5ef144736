// A child process (a fleetloc daemon, ddsperf) started with arguments, optional extra environment
// and its output in a log file, and stopped with a signal. Used by fleetctl's benchmarks and by
// the integration and fault tests.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::runtime {

class ChildProcess {
 public:
  // Starts `program` (a path) with `args`; stdout and stderr go to `log_path` (truncated);
  // `env` entries ("NAME=value") are added to this process's environment.
  static Result<ChildProcess> Start(const std::string& program,
                                    const std::vector<std::string>& args,
                                    const std::string& log_path,
                                    const std::vector<std::string>& env = {});
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&& other) noexcept;
  ~ChildProcess();  // kills (SIGKILL) and reaps a child still running

  bool Running();
  // Sends `signal` and waits up to `limit` for the exit. Returns the exit status (128 + signal
  // when a signal ended it), or -1 if it was still running at the limit (it is then killed).
  int Stop(int signal, std::chrono::milliseconds limit = std::chrono::seconds(15));
  // Waits up to `limit` for the child to exit by itself; exit status as Stop, -1 on time-out
  // (the child keeps running).
  int Wait(std::chrono::milliseconds limit);
  pid_t pid() const { return pid_; }

 private:
  explicit ChildProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_ = -1;
  int exit_status_ = -1;
};

// The directory of the running executable (for finding sibling programs in build/bin).
std::string ExecutableDir();

// What a running process has used so far, from /proc (zeros for a process that is gone).
struct ProcessUsage {
  double cpu_s = 0;        // user + system
  double rss_mb = 0;       // resident now
  double peak_rss_mb = 0;  // resident high-water mark
};
ProcessUsage UsageOf(pid_t pid);

}  // namespace fleetloc::runtime
