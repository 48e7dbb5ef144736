// fleetctl bench supervisor-abuse: a real fleet_supervisor (and a map server, so POST /api/remap
// starts real jobs) first idle, then under hostile clients (http_abuse.h: idle sockets, live
// streams half of which never read, slow senders, a header flood) while an operator's client
// keeps calling GET /api/fleet and POST /api/remap; the latency of each (p50, p99, max), the
// requests that failed, and the supervisor's resident memory (sampled, and its high-water mark).
// No assertions: numbers for docs/benchmarks.md.
// clang-format off
#include "mosaic/importer.h"  // Eigen before httplib (<resolv.h> defines `_res`)
#include <httplib.h>
// clang-format on
#include "harness/supervisor/bench_supervisor_abuse.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "harness/supervisor/http_abuse.h"
#include "io/file_util.h"
#include "replay/replay.h"
#include "runtime/child_process.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kToken = "bench-abuse-token-0123456789";

// Latencies (ms) and failures of one kind of request.
struct Series {
  std::vector<double> ms;
  int failed = 0;
  nlohmann::json Summary() const {
    return {{"requests", ms.size() + static_cast<size_t>(failed)},
            {"failed", failed},
            {"p50_ms", replay::Percentile(ms, 50)},
            {"p99_ms", replay::Percentile(ms, 99)},
            {"max_ms", ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end())}};
  }
};

struct Phase {
  Series fleet, remap;
  double max_rss_mb = 0;
};

// One timed request; `ok` decides whether its answer counts as served.
template <typename Call, typename Ok>
void Timed(Series* series, Call call, Ok ok) {
  const auto start = Clock::now();
  auto result = call();
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  if (result && ok(*result)) {
    series->ms.push_back(ms);
  } else {
    ++series->failed;
  }
}

// The operator's client for `seconds`: GET /api/fleet and POST /api/remap at `hz`.
Phase Measure(int port, pid_t supervisor, double seconds, double hz) {
  httplib::Client http("127.0.0.1", port);
  http.set_connection_timeout(10);
  http.set_read_timeout(10);
  const httplib::Headers maintainer = {{"Authorization", std::string("Bearer ") + kToken}};
  Phase phase;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / hz));
  for (auto next = Clock::now(); Clock::now() < end; next += period) {
    Timed(
        &phase.fleet, [&] { return http.Get("/api/fleet"); },
        [](const httplib::Response& r) { return r.status == 200; });
    Timed(
        &phase.remap,
        [&] {
          return http.Post("/api/remap", maintainer,
                           R"({"region": [0, 0, 0.05, 0.05], "mode": "blend"})",
                           "application/json");
        },
        [](const httplib::Response& r) { return r.status == 202; });
    phase.max_rss_mb = std::max(phase.max_rss_mb, runtime::UsageOf(supervisor).rss_mb);
    std::this_thread::sleep_until(next + period);
  }
  return phase;
}

// Starts a daemon from build/bin that writes its port to `port_file` (0 when it did not start).
Result<runtime::ChildProcess> StartDaemon(const std::string& name,
                                          const std::vector<std::string>& args,
                                          const std::string& work_dir) {
  return runtime::ChildProcess::Start(runtime::ExecutableDir() + "/" + name, args,
                                      work_dir + "/" + name + ".log");
}

int WaitForPort(const std::string& port_file) {
  int port = 0;
  for (int i = 0; i < 200 && port <= 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::ifstream(port_file) >> port;
  }
  return port;
}

// A small random-texture mosaic for the map server (the jobs find no patches: each is quick).
Status MakeMosaic(const std::string& work_dir, std::string* path) {
  cv::Mat floor(1024, 1024, CV_8UC1);
  cv::randu(floor, 0, 256);
  const std::string image = work_dir + "/floor.png";
  if (!cv::imwrite(image, floor)) return Internal("cannot write " + image);
  *path = work_dir + "/floor.db";
  fs::remove(*path);
  mosaic::ImportOptions options;
  options.resolution_m = 0.0005;
  Result<mosaic::MosaicLayout> imported = mosaic::ImportImage(image, options, *path);
  return imported.ok() ? Status::Ok() : imported.status();
}

void Print(const char* title, const Phase& p) {
  for (const auto& [name, s] :
       {std::pair{"GET /api/fleet", &p.fleet}, std::pair{"POST /api/remap", &p.remap}}) {
    const nlohmann::json j = s->Summary();
    std::printf("%-14s %-16s %6d requests %4d failed  p50 %7.1f ms  p99 %7.1f ms  max %7.1f ms\n",
                title, name, j["requests"].get<int>(), j["failed"].get<int>(),
                j["p50_ms"].get<double>(), j["p99_ms"].get<double>(), j["max_ms"].get<double>());
  }
}

// Until the map server listens for re-mapping commands (a job is accepted), at most 10 s.
void WaitForRemapCommands(httplib::Client& http) {
  for (int i = 0; i < 100; ++i) {
    const httplib::Headers maintainer = {{"Authorization", std::string("Bearer ") + kToken}};
    auto r = http.Post("/api/remap", maintainer, R"({"region": [0, 0, 0.05, 0.05]})",
                       "application/json");
    if (r && r->status == 202) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

nlohmann::json AbuseJson(const SupervisorAbuseBenchArgs& a, const AbuseStats& attack,
                         const Phase& idle, const Phase& attacked, double peak_rss,
                         const nlohmann::json& counters) {
  return {{"attack",
           {{"idle", a.abuse.idle},
            {"streams", a.abuse.streams},
            {"slow", a.abuse.slow},
            {"flood_mb", a.abuse.flood_mb},
            {"connects", attack.connects},
            {"closed_by_server", attack.closed_by_server},
            {"streams_answered", attack.streams_answered},
            {"streams_refused", attack.streams_refused},
            {"flood_mb_sent", attack.flood_mb_sent}}},
          {"idle",
           {{"fleet", idle.fleet.Summary()},
            {"remap", idle.remap.Summary()},
            {"max_rss_mb", idle.max_rss_mb}}},
          {"attacked",
           {{"fleet", attacked.fleet.Summary()},
            {"remap", attacked.remap.Summary()},
            {"max_rss_mb", attacked.max_rss_mb}}},
          {"supervisor_peak_rss_mb", peak_rss},
          {"supervisor_counters", counters}};
}

}  // namespace

Status RunSupervisorAbuseBench(SupervisorAbuseBenchArgs a) {
  const long files = io::RaiseOpenFileLimit();
  if (files < a.abuse.idle + a.abuse.streams + a.abuse.slow + 64) {
    return InvalidInput("the open-file limit " + std::to_string(files) + " is too low for " +
                        std::to_string(a.abuse.idle + a.abuse.streams + a.abuse.slow) +
                        " sockets (ulimit -n)");
  }
  fs::create_directories(a.work_dir);
  std::string mosaic;
  FLEETLOC_RETURN_IF_ERROR(MakeMosaic(a.work_dir, &mosaic));
  const std::string token_file = a.work_dir + "/token", port_file = a.work_dir + "/port";
  std::ofstream(token_file) << kToken << "\n";
  fs::permissions(token_file, fs::perms::owner_read | fs::perms::owner_write);
  fs::remove(port_file);
  fs::remove(a.work_dir + "/history.db");
  auto map_server = StartDaemon(
      "map_server", {"--mosaic", mosaic, "--domain", std::to_string(a.domain)}, a.work_dir);
  if (!map_server.ok()) return map_server.status();
  auto supervisor =
      StartDaemon("fleet_supervisor",
                  {"--domain", std::to_string(a.domain), "--history", a.work_dir + "/history.db",
                   "--http-port", "0", "--port-file", port_file, "--token-file", token_file},
                  a.work_dir);
  if (!supervisor.ok()) return supervisor.status();
  a.abuse.port = WaitForPort(port_file);
  if (a.abuse.port <= 0)
    return Internal("the supervisor did not start; see " + a.work_dir + "/fleet_supervisor.log");
  httplib::Client http("127.0.0.1", a.abuse.port);
  WaitForRemapCommands(http);
  const Phase idle = Measure(a.abuse.port, supervisor->pid(), a.idle_seconds, a.requests_hz);
  HttpAbuse abuse(a.abuse);
  abuse.Start();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const Phase attacked = Measure(a.abuse.port, supervisor->pid(), a.seconds, a.requests_hz);
  auto stats = http.Get("/api/stats");
  abuse.Stop();
  const AbuseStats attack = abuse.stats();
  const double peak_rss = runtime::UsageOf(supervisor->pid()).peak_rss_mb;
  const nlohmann::json out =
      AbuseJson(a, attack, idle, attacked, peak_rss,
                stats ? nlohmann::json::parse(stats->body, nullptr, false) : nlohmann::json());
  std::printf(
      "supervisor under %d idle sockets, %d live streams (half never read), %d slow senders and "
      "a %.0f MB header flood (%.0f MB sent, %lld connections)\n",
      a.abuse.idle, a.abuse.streams, a.abuse.slow, a.abuse.flood_mb, attack.flood_mb_sent,
      attack.connects);
  Print("idle", idle);
  Print("under attack", attacked);
  std::printf(
      "supervisor RSS: %.1f MB max idle, %.1f MB max under attack, high-water mark %.1f MB\n",
      idle.max_rss_mb, attacked.max_rss_mb, peak_rss);
  if (!a.json.empty()) std::ofstream(a.json) << out.dump(2) << "\n";
  const bool stopped = supervisor->Stop(SIGTERM) == 0;
  (void)map_server->Stop(SIGTERM);
  return stopped ? Status::Ok() : Internal("the supervisor did not stop cleanly");
}

}  // namespace fleetloc::bench
