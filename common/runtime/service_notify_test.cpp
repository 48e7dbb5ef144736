// ServiceNotifier against a test-owned NOTIFY_SOCKET, with a fake clock.
#include "runtime/service_notify.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "runtime/notify_listener.h"

namespace fleetloc::runtime {
namespace {

using namespace std::chrono_literals;
using testing::HasLine;
using testing::NotifyListener;

// Sets NOTIFY_SOCKET and WATCHDOG_USEC for one test and clears them after.
class SystemdEnvironment {
 public:
  SystemdEnvironment(const std::string& socket, const char* watchdog_usec) {
    setenv("NOTIFY_SOCKET", socket.c_str(), 1);
    if (watchdog_usec != nullptr) setenv("WATCHDOG_USEC", watchdog_usec, 1);
  }
  ~SystemdEnvironment() {
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
  }
};

TEST(ServiceNotifier, FirstCycleReportsReadyThenPingsEveryHalfWatchdogInterval) {
  NotifyListener listener;
  SystemdEnvironment env(listener.path(), "1000000");  // WatchdogSec=1
  ServiceNotifier::Clock::time_point now{};
  ServiceNotifier notifier([&] { return now; });
  ASSERT_TRUE(notifier.watchdog_enabled());
  EXPECT_EQ(notifier.watchdog_interval(), 1s);

  notifier.Alive();
  EXPECT_TRUE(HasLine(listener.Receive(1s), "READY=1"));
  int pings = 0;
  for (int cycle = 0; cycle < 40; ++cycle) {  // 2 s of 50 ms cycles
    now += 50ms;
    notifier.Alive();
  }
  for (std::string m = listener.Receive(100ms); !m.empty(); m = listener.Receive(100ms)) {
    EXPECT_TRUE(HasLine(m, "WATCHDOG=1")) << m;
    ++pings;
  }
  EXPECT_EQ(pings, 4) << "one ping per 500 ms over 2 s";
}

TEST(ServiceNotifier, WithoutWatchdogOnlyReadyAndStoppingAreSent) {
  NotifyListener listener;
  SystemdEnvironment env(listener.path(), nullptr);
  ServiceNotifier::Clock::time_point now{};
  ServiceNotifier notifier([&] { return now; });
  EXPECT_FALSE(notifier.watchdog_enabled());
  for (int cycle = 0; cycle < 10; ++cycle, now += 1s) notifier.Alive();
  notifier.Stopping();
  EXPECT_TRUE(HasLine(listener.Receive(1s), "READY=1"));
  EXPECT_TRUE(HasLine(listener.Receive(1s), "STOPPING=1"));
  EXPECT_EQ(listener.Receive(100ms), "");
}

TEST(ServiceNotifier, NotStartedBySystemdSendsNothingAndDoesNotFail) {
  unsetenv("NOTIFY_SOCKET");
  ServiceNotifier notifier;
  EXPECT_FALSE(notifier.watchdog_enabled());
  notifier.Alive();
  notifier.Alive();
  notifier.Stopping();
}

}  // namespace
}  // namespace fleetloc::runtime
