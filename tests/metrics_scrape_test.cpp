// Prometheus /metrics on every service, scraped over HTTP while a vehicle drives: a map server, a
// fleet supervisor and a tracker agent (metrics enabled) on their own DDS domain; every line of
// each answer must be valid text exposition format, and the counters, histograms and gauges the
// issue names must be there and move. Also: silent clients on the supervisor's metrics port do not
// stall it, and a metrics port already taken is logged and leaves the service running.
// Eigen (through the fixtures) before httplib: <resolv.h> defines a macro that breaks Eigen.
// clang-format off: Eigen before httplib (<resolv.h> defines `_res`, a name Eigen's headers use)
#include <Eigen/Core>
// clang-format on
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <regex>

#include "io/loopback_socket.h"
#include "map_server_fixture.h"
#include "metrics/exposition.h"
#include "supervisor_fixture.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 121;

int ReadPort(const std::string& file) {
  int port = 0;
  Eventually(
      [&] {
        std::ifstream in(file);
        return static_cast<bool>(in >> port) && port > 0;
      },
      20);
  return port;
}

// Scrapes http://127.0.0.1:<port>/metrics and parses every line (failing the test on a bad one).
metrics::Exposition Scrape(int port, int timeout_s = 5) {
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(timeout_s, 0);
  httplib::Result r = client.Get("/metrics");
  if (!r) {
    ADD_FAILURE() << "no answer from :" << port << "/metrics";
    return {};
  }
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->get_header_value("Content-Type").find("text/plain"), std::string::npos);
  Result<metrics::Exposition> e = metrics::ParseExposition(r->body);
  if (!e.ok()) {
    ADD_FAILURE() << "port " << port << ": " << e.status().message() << "\n" << r->body;
    return {};
  }
  return *e;
}

double ValueOr(const metrics::Exposition& e, const std::string& name,
               const std::map<std::string, std::string>& labels = {}) {
  Result<double> v = e.Value(name, labels);
  return v.ok() ? *v : -1;
}

int ConnectSilently(int port) {
  const int fd = io::ConnectLoopback(port);
  EXPECT_GE(fd, 0);
  return fd;
}

TEST(MetricsScrape, EveryServiceServesValidMetricsThatMoveWhileAVehicleDrives) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  const std::string tmp = ::testing::TempDir() + "/metrics_scrape_";
  for (const char* f : {"ms", "sup", "agent"}) std::filesystem::remove(tmp + f);
  testing::MapServerFixture server("metrics_scrape", floor, kDomain, 0.0005, 256,
                                   "\"metrics\": {\"port\": 0, \"port_file\": \"" + tmp + "ms\"}");
  std::filesystem::create_directories(server.dir() / "sup");
  testing::SupervisorProcess supervisor(
      server.dir() / "sup", kDomain, "metrics-scrape-token-0123",
      {"--metrics-port", "0", "--metrics-port-file", tmp + "sup"});
  const std::string run = (server.dir() / "run").string();
  ASSERT_EQ(testing::RunFleetctl("sim --mosaic " + server.mosaic_path() +
                                 " --frames 60 --seed 5 --out " + run)
                .exit_code,
            0);
  runtime::ChildProcess agent =
      testing::StartDaemon("tracker_agent",
                           {"--run", run, "--domain", std::to_string(kDomain), "--vehicle-id",
                            "agv-m", "--outbox", (server.dir() / "outbox.db").string(),
                            "--metrics-port", "0", "--metrics-port-file", tmp + "agent"},
                           (server.dir() / "agent.log").string());
  const int ms_port = ReadPort(tmp + "ms"), sup_port = ReadPort(tmp + "sup"),
            agent_port = ReadPort(tmp + "agent");
  ASSERT_GT(ms_port, 0);
  ASSERT_GT(sup_port, 0) << supervisor.log();
  ASSERT_GT(agent_port, 0);

  // The agent: frames, cycle times and tile round trips counted, its lock state set.
  metrics::Exposition a;
  EXPECT_TRUE(Eventually(
      [&] {
        a = Scrape(agent_port);
        return ValueOr(a, "fleetloc_agent_frames_total") >= 10 &&
               ValueOr(a, "fleetloc_agent_tile_round_trip_seconds_count") > 0;
      },
      30))
      << "agent metrics never moved";
  EXPECT_EQ(a.types["fleetloc_agent_cycle_seconds"], "histogram");
  EXPECT_GE(ValueOr(a, "fleetloc_agent_cycle_seconds_count", {{"vehicle_id", "agv-m"}}), 10);
  EXPECT_EQ(ValueOr(a, "fleetloc_agent_lock_state", {{"lock_state", "tracking"}}), 1);
  EXPECT_GE(ValueOr(a, "fleetloc_agent_tile_cache_hit_ratio"), 0);
  EXPECT_GE(ValueOr(a, "fleetloc_agent_patch_outbox_patches"), 0);

  // The map server: tiles served and their reply latency, cache hit ratio.
  metrics::Exposition m;
  EXPECT_TRUE(Eventually(
      [&] {
        m = Scrape(ms_port);
        return ValueOr(m, "fleetloc_map_server_tiles_served_total") > 0;
      },
      10));
  EXPECT_GT(ValueOr(m, "fleetloc_map_server_tile_reply_seconds_count", {{"service_id", "map-t"}}),
            0);
  EXPECT_GE(ValueOr(m, "fleetloc_map_server_tile_cache_hit_ratio"), 0);
  EXPECT_EQ(ValueOr(m, "fleetloc_map_server_rejected_tile_request_total"), 0);

  // The supervisor: the vehicle counted by lock state, its health gauges, the supervisor's
  // counters.
  metrics::Exposition s;
  EXPECT_TRUE(Eventually(
      [&] {
        s = Scrape(sup_port);
        return ValueOr(s, "fleetloc_supervisor_vehicles", {{"lock_state", "tracking"}}) == 1 &&
               ValueOr(s, "fleetloc_supervisor_vehicle_patch_outbox_patches",
                       {{"vehicle_id", "agv-m"}}) >= 0;
      },
      10))
      << "the supervisor never counted the tracking vehicle";
  EXPECT_GT(ValueOr(s, "fleetloc_supervisor_poses_received_total"), 0);
  EXPECT_EQ(ValueOr(s, "fleetloc_supervisor_map_server_alive"), 1);
  EXPECT_GT(ValueOr(s, "fleetloc_supervisor_vehicle_cycle_seconds",
                    {{"vehicle_id", "agv-m"}, {"quantile", "0.95"}}),
            0);
  EXPECT_EQ(s.types["fleetloc_supervisor_history_queue"], "gauge");

  // Every metric the shipped alert rules use is served.
  std::ifstream rules_file(FLEETLOC_SOURCE_DIR "/deploy/prometheus/fleetloc_alerts.yml");
  const std::string rules((std::istreambuf_iterator<char>(rules_file)),
                          std::istreambuf_iterator<char>());
  const std::regex name(R"((^|[^"])(fleetloc_[a-z_]+))");  // not job names ("fleetloc_...")
  int names = 0;
  for (auto it = std::sregex_iterator(rules.begin(), rules.end(), name);
       it != std::sregex_iterator(); ++it, ++names) {
    const std::string metric = (*it)[2].str();
    bool served = false;
    for (const metrics::Exposition* e : {&a, &m, &s}) {
      for (const metrics::Sample& sample : e->samples) served = served || sample.name == metric;
    }
    EXPECT_TRUE(served) << "deploy/prometheus/fleetloc_alerts.yml uses " << metric
                        << ", which no service serves";
  }
  EXPECT_GE(names, 7);

  // Silent clients hogging the metrics port: the supervisor's API still answers at once, and a
  // scrape gets through once they are cut off (request timeout 2 s each, one metrics thread).
  std::vector<int> silent;
  for (int i = 0; i < 3; ++i) silent.push_back(ConnectSilently(sup_port));
  httplib::Client api("127.0.0.1", supervisor.port());
  const auto start = std::chrono::steady_clock::now();
  httplib::Result stats = api.Get("/api/stats");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  ASSERT_TRUE(stats);
  EXPECT_EQ(stats->status, 200);
  const auto scrape_start = std::chrono::steady_clock::now();
  EXPECT_GT(ValueOr(Scrape(sup_port, 15), "fleetloc_supervisor_poses_received_total"), 0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - scrape_start).count(),
            3 * 2.0 + 2);
  for (int fd : silent) ::close(fd);
  agent.Stop(SIGTERM);
}

TEST(MetricsScrape, AMetricsPortInUseIsLoggedAndTheServiceRunsOn) {
  const std::string dir = ::testing::TempDir() + "/metrics_taken";
  std::filesystem::create_directories(dir);
  httplib::Server squatter;
  const int taken = squatter.bind_to_any_port("127.0.0.1");
  std::thread serving([&] { squatter.listen_after_bind(); });
  {
    testing::SupervisorProcess supervisor(dir, kDomain, "metrics-scrape-token-0123",
                                          {"--metrics-port", std::to_string(taken)});
    httplib::Client api("127.0.0.1", supervisor.port());
    httplib::Result stats = api.Get("/api/stats");
    ASSERT_TRUE(stats);
    EXPECT_EQ(stats->status, 200);
    EXPECT_TRUE(Eventually(
        [&] { return supervisor.log().find("running without /metrics") != std::string::npos; }, 5))
        << supervisor.log();
    EXPECT_NE(supervisor.log().find("127.0.0.1:" + std::to_string(taken)), std::string::npos);
  }
  squatter.stop();
  serving.join();
}

}  // namespace
}  // namespace fleetloc
