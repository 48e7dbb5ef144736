// systemd readiness and watchdog of every daemon (issue 22), with the test in systemd's place: it
// owns NOTIFY_SOCKET and sets WATCHDOG_USEC as systemd does for Type=notify, WatchdogSec=1 (this
// container runs no systemd to start the units). Each service must report READY=1, then feed the
// watchdog from its main loop; when the loop hangs (fault hook FLEETLOC_FAULT_HANG_AFTER_S) the
// pings stop while the process lives on, which is what makes systemd kill and restart it.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_runner.h"
#include "daemon_process.h"
#include "mosaic/importer.h"
#include "runtime/notify_listener.h"

namespace fleetloc {
namespace {

using namespace std::chrono_literals;
using runtime::testing::HasLine;
using runtime::testing::NotifyListener;

constexpr uint32_t kDomain = 131;

// The environment systemd gives a Type=notify service with WatchdogSec=1, plus the hang hook.
std::vector<std::string> SystemdEnvironment(const NotifyListener& listener, double hang_after_s) {
  std::vector<std::string> env = {"NOTIFY_SOCKET=" + listener.path(), "WATCHDOG_USEC=1000000"};
  if (hang_after_s > 0)
    env.push_back("FLEETLOC_FAULT_HANG_AFTER_S=" + std::to_string(hang_after_s));
  return env;
}

int CountLine(const std::vector<std::string>& messages, const std::string& line) {
  return static_cast<int>(std::count_if(messages.begin(), messages.end(),
                                        [&](const std::string& m) { return HasLine(m, line); }));
}

// A 2048 px square floor (gravel.png repeated) imported as a mosaic `dir/floor.db`.
void MakeFloor(const testing::ScratchDir& dir) {
  const cv::Mat gravel =
      cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  cv::Mat floor;
  cv::repeat(gravel, 4, 4, floor);
  ASSERT_TRUE(cv::imwrite(dir / "floor.png", floor));
  mosaic::ImportOptions options;
  options.resolution_m = 0.0005;
  auto imported = mosaic::ImportImage(dir / "floor.png", options, dir / "floor.db");
  ASSERT_TRUE(imported.ok()) << imported.status().message();
}

runtime::ChildProcess StartMapServer(const testing::ScratchDir& dir,
                                     const std::vector<std::string>& env) {
  return testing::StartDaemon("map_server",
                              {"--mosaic", dir / "floor.db", "--domain", std::to_string(kDomain)},
                              dir / "map_server.log", env);
}

// The watchdog's life: READY=1 once set up, WATCHDOG=1 about twice a second (WatchdogSec=1)
// while the loop runs, and none after the loop hangs at `hang_after` (the process still running,
// for systemd to kill).
void ExpectReadyPingsThenSilence(NotifyListener& listener, runtime::ChildProcess& process,
                                 const std::string& log) {
  std::string first;
  for (auto end = std::chrono::steady_clock::now() + 40s;
       first.empty() && std::chrono::steady_clock::now() < end;) {
    first = listener.Receive(1s);
  }
  ASSERT_TRUE(HasLine(first, "READY=1")) << "no readiness; log:\n" << testing::ReadWhole(log);
  const std::vector<std::string> running = listener.ReceiveFor(3s);
  EXPECT_GE(CountLine(running, "WATCHDOG=1"), 4) << "too few pings while running";
  EXPECT_LE(CountLine(running, "WATCHDOG=1"), 8) << "pinged far more often than needed";
  (void)listener.ReceiveFor(4s);  // the hook hangs the loop 5 s after the first cycle
  const std::vector<std::string> hung = listener.ReceiveFor(3s);
  EXPECT_EQ(CountLine(hung, "WATCHDOG=1"), 0) << "a hung main loop still fed the watchdog";
  EXPECT_TRUE(process.Running()) << "the hung service exited instead of hanging";
  EXPECT_NE(testing::ReadWhole(log).find("main loop hung"), std::string::npos);
}

TEST(ServiceWatchdog, MapServerFeedsTheWatchdogUntilItsLoopHangs) {
  testing::ScratchDir dir("watchdog_map_server");
  MakeFloor(dir);
  NotifyListener listener;
  runtime::ChildProcess server = StartMapServer(dir, SystemdEnvironment(listener, 5));
  ExpectReadyPingsThenSilence(listener, server, dir / "map_server.log");
}

TEST(ServiceWatchdog, SupervisorFeedsTheWatchdogUntilItsLoopHangs) {
  testing::ScratchDir dir("watchdog_supervisor");
  NotifyListener listener;
  runtime::ChildProcess supervisor = testing::StartDaemon(
      "fleet_supervisor",
      {"--domain", std::to_string(kDomain), "--history", dir / "history.db", "--http-port", "0"},
      dir / "fleet_supervisor.log", SystemdEnvironment(listener, 5));
  ExpectReadyPingsThenSilence(listener, supervisor, dir / "fleet_supervisor.log");
}

TEST(ServiceWatchdog, TrackerAgentFeedsTheWatchdogUntilItsLoopHangs) {
  testing::ScratchDir dir("watchdog_agent");
  MakeFloor(dir);
  runtime::ChildProcess server = StartMapServer(dir, {});
  const nlohmann::json config{{"vehicle_id", "agv-w"},
                              {"domain", kDomain},
                              {"source", "sim"},
                              {"sim_floor", dir / "floor.png"},
                              {"mosaic_wait_s", 20}};
  std::ofstream(dir / "agent.json") << config.dump(2);
  NotifyListener listener;
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent", {"--config", dir / "agent.json", "--outbox", dir / "outbox.db"},
      dir / "agent.log", SystemdEnvironment(listener, 5));
  ExpectReadyPingsThenSilence(listener, agent, dir / "agent.log");
  EXPECT_EQ(server.Stop(SIGTERM), 0);
}

TEST(ServiceWatchdog, CleanStopReportsStoppingAndExitsZero) {
  testing::ScratchDir dir("watchdog_stop");
  MakeFloor(dir);
  NotifyListener listener;
  runtime::ChildProcess server = StartMapServer(dir, SystemdEnvironment(listener, 0));
  std::string first;
  for (auto end = std::chrono::steady_clock::now() + 30s;
       first.empty() && std::chrono::steady_clock::now() < end;) {
    first = listener.Receive(1s);
  }
  ASSERT_TRUE(HasLine(first, "READY=1"));
  EXPECT_EQ(server.Stop(SIGTERM), 0);
  EXPECT_EQ(CountLine(listener.ReceiveFor(500ms), "STOPPING=1"), 1);
}

}  // namespace
}  // namespace fleetloc
