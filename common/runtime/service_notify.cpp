// sd_notify through libsystemd (rather than a hand-written datagram: it knows abstract socket
// names, WATCHDOG_PID and the message rules systemd expects), plus the test-only hang hook.
#include "runtime/service_notify.h"

#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>

#include <cstdlib>
#include <cstring>
#include <optional>
#include <thread>

namespace fleetloc::runtime {

ServiceNotifier::ServiceNotifier(std::function<Clock::time_point()> now) : now_(std::move(now)) {
  uint64_t usec = 0;
  if (sd_watchdog_enabled(/*unset_environment=*/0, &usec) > 0) {
    watchdog_interval_ = std::chrono::microseconds(usec);
  }
}

void ServiceNotifier::Alive() {
  const Clock::time_point now = now_();
  if (!ready_sent_) {
    ready_sent_ = true;
    last_ping_ = now;
    const int sent = sd_notify(0, "READY=1\nSTATUS=serving");
    if (sent < 0) spdlog::warn("systemd notification failed: {}", std::strerror(-sent));
    if (sent > 0 && watchdog_enabled()) {
      spdlog::info("systemd watchdog: a ping every {} ms", watchdog_interval_.count() / 2000);
    }
    return;
  }
  if (!watchdog_enabled() || now - last_ping_ < watchdog_interval_ / 2) return;
  last_ping_ = now;
  (void)sd_notify(0, "WATCHDOG=1");  // a failure here shows as a watchdog restart
}

void ServiceNotifier::Stopping() { (void)sd_notify(0, "STOPPING=1\nSTATUS=stopping"); }

namespace {

ServiceNotifier& ProcessNotifier() {
  static ServiceNotifier notifier;
  return notifier;
}

// The fault hook's deadline (none unless FLEETLOC_FAULT_HANG_AFTER_S is set), from the first call.
std::optional<ServiceNotifier::Clock::time_point> HangDeadline() {
  static const std::optional<ServiceNotifier::Clock::time_point> deadline =
      []() -> std::optional<ServiceNotifier::Clock::time_point> {
    const char* after = std::getenv("FLEETLOC_FAULT_HANG_AFTER_S");
    if (after == nullptr) return std::nullopt;
    spdlog::warn("fault hook: the main loop hangs in {} s (FLEETLOC_FAULT_HANG_AFTER_S)", after);
    return ServiceNotifier::Clock::now() +
           std::chrono::duration_cast<ServiceNotifier::Clock::duration>(
               std::chrono::duration<double>(std::atof(after)));
  }();
  return deadline;
}

}  // namespace

void NotifyServiceAlive() {
  if (auto deadline = HangDeadline(); deadline && ServiceNotifier::Clock::now() >= *deadline) {
    spdlog::warn("fault hook: main loop hung");
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
  }
  ProcessNotifier().Alive();
}

void NotifyServiceStopping() { ProcessNotifier().Stopping(); }

}  // namespace fleetloc::runtime
