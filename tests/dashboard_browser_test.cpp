// The dashboard in a real browser against a real fleet: a map server on an imported demo floor,
// two tracker agents driving simulated vehicles over it, the fleet supervisor, and headless
// Debian chromium driven by playwright-core (tests/browser/dashboard_test.mjs). Screenshots are
// kept in build/test-artifacts/dashboard/.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "supervisor_fixture.h"

namespace fleetloc {
namespace {

constexpr uint32_t kDomain = 100;

TEST(DashboardBrowser, VehiclesMoveAKilledAgentRaisesAnAlertAndARemapFromThePageCompletes) {
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/chromium"))
      << "install Debian's chromium (tools/scripts/setup.sh)";
  const std::string node_dir = FLEETLOC_BINARY_DIR "/browser";
  const int installed =
      std::system((FLEETLOC_SOURCE_DIR "/tests/browser/install_deps.sh " + node_dir).c_str());
  ASSERT_EQ(installed, 0) << "npm ci of tests/browser failed";

  const cv::Mat floor =
      cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/gravel_1024.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(floor.empty());
  testing::MapServerFixture server("dashboard_browser", floor, kDomain);
  const std::string floor_image = (server.dir() / "floor.png").string();
  std::vector<runtime::ChildProcess> agents;
  for (const std::string id : {"agv-b1", "agv-b2"}) {
    agents.push_back(testing::StartDaemon(
        "tracker_agent",
        {"--sim-floor", floor_image, "--domain", std::to_string(kDomain), "--vehicle-id", id,
         "--outbox", (server.dir() / (id + "_outbox.db")).string()},
        (server.dir() / (id + ".log")).string()));
  }
  const std::string config = (server.dir() / "supervisor.json").string();
  std::ofstream(config) << R"({"mosaic_name": "Hall 3 floor"})";
  testing::SupervisorProcess supervisor(server.dir(), kDomain, "maint-7f3a9c-7f3a9c",
                                        {"--config", config});
  ASSERT_GT(supervisor.port(), 0);

  const std::string artifacts = FLEETLOC_BINARY_DIR "/test-artifacts/dashboard";
  const std::string log = (server.dir() / "browser.log").string();
  auto browser = runtime::ChildProcess::Start(
      "/usr/bin/env",
      {"node", FLEETLOC_SOURCE_DIR "/tests/browser/dashboard_test.mjs", "--url", supervisor.url(),
       "--token", supervisor.token(), "--kill-pid", std::to_string(agents[1].pid()),
       "--kill-vehicle", "agv-b2", "--out", artifacts, "--mosaic-name", "Hall 3 floor"},
      log, {"FLEETLOC_NODE_MODULES=" + node_dir + "/node_modules"});
  ASSERT_TRUE(browser.ok()) << browser.status().message();
  const int status = browser->Wait(std::chrono::seconds(240));
  const std::string output = testing::ReadWhole(log);
  std::cout << output;
  EXPECT_EQ(status, 0) << "browser test failed; supervisor log:\n" << supervisor.log();
  for (const char* shot : {"03_remap_done.png", "05_map_checks.png", "06_ellipse_zoom_max.png",
                           "07_follow.png", "08_plots.png", "09_1024px.png"}) {
    EXPECT_TRUE(std::filesystem::exists(artifacts + "/" + shot)) << shot;
  }
  EXPECT_EQ(agents[0].Stop(SIGINT), 0);
}

}  // namespace
}  // namespace fleetloc
