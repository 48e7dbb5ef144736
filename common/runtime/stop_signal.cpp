// Signal handlers setting the process-wide stop flag.
#include "runtime/stop_signal.h"

#include <csignal>

namespace fleetloc::runtime {
namespace {

std::atomic<bool> stop_requested{false};

extern "C" void OnStopSignal(int signal_number) {
  if (stop_requested.exchange(true)) std::signal(signal_number, SIG_DFL);
}

}  // namespace

const std::atomic<bool>& InstallStopSignals() {
  static_assert(std::atomic<bool>::is_always_lock_free);  // safe in a signal handler
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  return stop_requested;
}

}  // namespace fleetloc::runtime
