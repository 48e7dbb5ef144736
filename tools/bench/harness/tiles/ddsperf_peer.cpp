// Runs ddsperf pub/sub and ping/pong and parses their per-second report lines.
#include "harness/tiles/ddsperf_peer.h"

#include <signal.h>

#include <fstream>
#include <regex>
#include <thread>

#include "replay/replay.h"
#include "runtime/child_process.h"

namespace fleetloc::bench {
namespace {

constexpr const char* kDdsperf = "/usr/bin/ddsperf";

// Runs ddsperf `server_args` in the background and `client_args` until it exits (about
// `seconds`); returns the server's log if `want_server_log`, else the client's.
Result<std::string> RunPair(const std::vector<std::string>& server_args,
                            const std::vector<std::string>& client_args, double seconds,
                            const std::string& config_uri, const std::string& work_dir,
                            const std::string& name, bool want_server_log) {
  const std::vector<std::string> env{"CYCLONEDDS_URI=" + config_uri};
  const std::string server_log = work_dir + "/ddsperf_" + name + "_server.log";
  const std::string client_log = work_dir + "/ddsperf_" + name + "_client.log";
  auto server = runtime::ChildProcess::Start(kDdsperf, server_args, server_log, env);
  if (!server.ok()) return server.status();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  auto client = runtime::ChildProcess::Start(kDdsperf, client_args, client_log, env);
  if (!client.ok()) return client.status();
  const auto limit = std::chrono::milliseconds(static_cast<int>(seconds * 1000) + 15000);
  client->Wait(limit);
  server->Stop(SIGTERM, std::chrono::seconds(5));
  std::ifstream in(want_server_log ? server_log : client_log);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<double> Matches(const std::string& text, const std::regex& pattern) {
  std::vector<double> values;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern);
       it != std::sregex_iterator(); ++it) {
    values.push_back(std::stod((*it)[1].str()));
  }
  return values;
}

}  // namespace

Result<DdsperfThroughput> RunDdsperfThroughput(int domain, int size_bytes, double seconds,
                                               const std::string& config_uri,
                                               const std::string& work_dir) {
  const std::string d = std::to_string(domain),
                    secs = std::to_string(static_cast<int>(seconds) + 1);
  Result<std::string> log =
      RunPair({"-i", d, "-D", std::to_string(static_cast<int>(seconds) + 2), "sub"},
              {"-i", d, "-D", secs, "pub", "size", std::to_string(size_bytes)}, seconds, config_uri,
              work_dir, "throughput", true);
  if (!log.ok()) return log.status();
  // "... rate 64.72 kS/s 25888.80 Mb/s (...)": the first number after "rate" per line.
  std::vector<double> rates = Matches(*log, std::regex(R"(rate ([0-9.]+) kS/s)"));
  if (rates.size() < 2) return Internal("ddsperf sub reported no rates (" + work_dir + ")");
  rates.erase(rates.begin());  // the first second includes discovery
  DdsperfThroughput result;
  result.samples_per_s = replay::Percentile(rates, 50) * 1e3;
  result.megabytes_per_s = result.samples_per_s * size_bytes / 1e6;
  return result;
}

Result<DdsperfLatency> RunDdsperfPingPong(int domain, int size_bytes, double seconds,
                                          const std::string& config_uri,
                                          const std::string& work_dir) {
  const std::string d = std::to_string(domain);
  Result<std::string> log =
      RunPair({"-i", d, "-D", std::to_string(static_cast<int>(seconds) + 2), "pong"},
              {"-i", d, "-D", std::to_string(static_cast<int>(seconds) + 1), "ping", "size",
               std::to_string(size_bytes)},
              seconds, config_uri, work_dir, "pingpong", false);
  if (!log.ok()) return log.status();
  const std::vector<double> p50 = Matches(*log, std::regex(R"( 50% ([0-9.]+)us)"));
  const std::vector<double> p99 = Matches(*log, std::regex(R"( 99% ([0-9.]+)us)"));
  if (p50.empty() || p99.empty()) return Internal("ddsperf ping reported no round trips");
  return DdsperfLatency{replay::Percentile(p50, 50), replay::Percentile(p99, 50)};
}

}  // namespace fleetloc::bench
