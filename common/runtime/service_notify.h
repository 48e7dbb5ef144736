// systemd's service notification protocol for the daemons: READY=1 once the main loop runs,
// WATCHDOG=1 fed from that loop (so systemd restarts a hung service, WatchdogSec= in
// deploy/systemd) and STOPPING=1 on a clean stop. Without NOTIFY_SOCKET (not started by systemd
// with Type=notify) every call does nothing.
#pragma once

#include <chrono>
#include <functional>

namespace fleetloc::runtime {

// One service's notifications. Not thread-safe: a daemon calls it from its main loop only.
class ServiceNotifier {
 public:
  using Clock = std::chrono::steady_clock;
  // Reads NOTIFY_SOCKET, WATCHDOG_USEC and WATCHDOG_PID (through libsystemd). `now` is for tests.
  explicit ServiceNotifier(std::function<Clock::time_point()> now = Clock::now);

  // One main-loop cycle went round: the first call sends READY=1, later ones WATCHDOG=1 whenever
  // half the watchdog interval has passed since the last one (none without a watchdog).
  void Alive();
  // The service is shutting down cleanly (STOPPING=1).
  void Stopping();

  bool watchdog_enabled() const { return watchdog_interval_.count() > 0; }
  std::chrono::microseconds watchdog_interval() const { return watchdog_interval_; }

 private:
  std::function<Clock::time_point()> now_;
  std::chrono::microseconds watchdog_interval_{0};
  bool ready_sent_ = false;
  Clock::time_point last_ping_{};
};

// The process's notifier (made on first use), for the daemons' main loops. NotifyServiceAlive also
// honours the fault hook FLEETLOC_FAULT_HANG_AFTER_S=N: N seconds after the first call it never
// returns, like a hung main loop (tests/service_watchdog_test.cpp; never set in deployment).
void NotifyServiceAlive();
void NotifyServiceStopping();

}  // namespace fleetloc::runtime
