// fleetctl bench supervisor: a real fleet_supervisor process fed by N simulated vehicles from one
// participant (poses at --pose-hz, health at 1 Hz, stamped when published); measures whether it
// keeps up (samples received vs published, history queue), the end-to-end latency from a pose's
// publication to its first appearance in the live stream the dashboard reads (/api/events), and
// the supervisor's CPU and resident memory from /proc. No assertions: numbers for
// docs/benchmarks.md.
// clang-format off: first (Eigen before httplib, whose <resolv.h> defines `_res`).
#include "transport/pose_messages.h"  // Eigen before httplib (<resolv.h> defines `_res`)
// clang-format on

#include <httplib.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "harness/supervisor/bench_supervisor.h"
#include "replay/replay.h"
#include "runtime/child_process.h"
#include "transport/topic_names.h"
#include "transport/typed_io.h"
#include "transport/vehicle_streams.h"
#include "transport/wire_util.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// CPU seconds (user + system) and resident MB of a process, from /proc.
std::pair<double, double> CpuAndRss(pid_t pid) {
  const runtime::ProcessUsage usage = runtime::UsageOf(pid);
  return {usage.cpu_s, usage.rss_mb};
}

// Publishes the simulated fleet until `stop`: vehicle i drives a circle of its own.
void PublishFleet(const SupervisorBenchArgs& a, const std::atomic<bool>& stop,
                  std::atomic<long long>* published) {
  using namespace transport;
  auto participant = Participant::Create(a.domain);
  if (!participant.ok()) return spdlog::error("{}", participant.status().message());
  auto pose_topic = Topic<fleetloc_VehiclePose>::Create(*participant, topics::kVehiclePose);
  auto health_topic = Topic<fleetloc_VehicleHealth>::Create(*participant, topics::kVehicleHealth);
  if (!pose_topic.ok() || !health_topic.ok())
    return spdlog::error("bench: cannot create the topics");
  // Each vehicle writes in its own partition, as an agent does (transport/vehicle_streams.h).
  std::vector<VehicleStreamWriter<fleetloc_VehiclePose>> poses;
  std::vector<VehicleStreamWriter<fleetloc_VehicleHealth>> health;
  for (int i = 0; i < a.vehicles; ++i) {
    const std::string id = "sim-" + std::to_string(i);
    auto pose_writer = VehicleStreamWriter<fleetloc_VehiclePose>::Create(
        *participant, id, *pose_topic, PoseStreamQos());
    auto health_writer = VehicleStreamWriter<fleetloc_VehicleHealth>::Create(
        *participant, id, *health_topic, PeriodicStateQos(3, 5));
    if (!pose_writer.ok() || !health_writer.ok())
      return spdlog::error("bench: cannot create the writers");
    poses.push_back(std::move(pose_writer).value());
    health.push_back(std::move(health_writer).value());
  }
  while (!poses.empty() && poses.back().MatchedReaders() == 0 && !stop)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto period = std::chrono::duration<double>(1.0 / a.pose_hz);
  auto next = Clock::now();
  for (long long tick = 0; !stop; ++tick) {
    const double now = Now();
    for (int i = 0; i < a.vehicles; ++i) {
      PoseReport report{"sim-" + std::to_string(i), now, {}, tracking::LockState::kTracking, 1};
      const double phase = now * 0.2 + i;
      const int row = i / 25;  // 25 vehicles a row, 10 m apart
      report.base_in_map.pose = {10 * (i % 25) + std::cos(phase), 10 * row + std::sin(phase),
                                 phase + M_PI / 2};
      report.base_in_map.covariance = Eigen::Vector3d(1e-8, 1e-8, 1e-6).asDiagonal();
      if (poses[i].Write(ToIdl(report)).ok()) ++*published;
      if (tick % static_cast<long long>(std::max(1.0, a.pose_hz)) == 0) {
        fleetloc_VehicleHealth h{};
        h.wire_version = fleetloc_CURRENT_WIRE_VERSION;
        SetBounded(h.vehicle_id, report.vehicle_id);
        h.stamp = NowStamp();
        h.cycle_ms_p50 = 1.2f;
        h.cycle_ms_p95 = 1.9f;
        h.cycle_ms_p99 = 2.5f;
        h.inliers = 24;
        h.map_server_reachable = true;
        (void)health[i].Write(h);
      }
    }
    next += std::chrono::duration_cast<Clock::duration>(period);
    std::this_thread::sleep_until(next);
  }
}

// Reads the live stream; for each vehicle, a pose stamp seen for the first time gives one latency.
void ReadStream(int port, const std::atomic<bool>& stop, std::vector<double>* latencies_ms,
                std::mutex* mutex) {
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(5, 0);
  std::string buffer;
  std::map<std::string, double> last_stamp;
  (void)client.Get("/api/events", [&](const char* data, size_t n) {
    buffer.append(data, n);
    for (size_t end; (end = buffer.find("\n\n")) != std::string::npos; buffer.erase(0, end + 2)) {
      if (buffer.rfind("data: ", 0) != 0) continue;
      const double seen = Now();
      const nlohmann::json snapshot =
          nlohmann::json::parse(buffer.substr(6, end - 6), nullptr, false);
      if (snapshot.is_discarded()) continue;
      std::lock_guard lock(*mutex);
      for (const nlohmann::json& v : snapshot["vehicles"]) {
        if (v["pose"].is_null()) continue;
        const double t = v["pose"]["t"].get<double>();
        double& last = last_stamp[v["id"].get<std::string>()];
        if (t != last) {
          latencies_ms->push_back((seen - t) * 1e3);
          last = t;
        }
      }
    }
    return !stop.load();
  });
}

// A fleet_supervisor process on a fresh history and a free HTTP port (`port`).
Result<runtime::ChildProcess> StartSupervisor(const SupervisorBenchArgs& a, int* port) {
  fs::create_directories(a.work_dir);
  const std::string port_file = a.work_dir + "/port", history = a.work_dir + "/history.db";
  fs::remove(port_file);
  fs::remove(history);
  std::vector<std::string> args = {
      "--domain", std::to_string(a.domain), "--history", history, "--http-port", "0", "--port-file",
      port_file,  "--metrics-port",         "0"};
  if (!a.supervisor_config.empty()) args.insert(args.end(), {"--config", a.supervisor_config});
  auto supervisor = runtime::ChildProcess::Start(runtime::ExecutableDir() + "/fleet_supervisor",
                                                 args, a.work_dir + "/fleet_supervisor.log");
  if (!supervisor.ok()) return supervisor.status();
  *port = 0;
  for (int i = 0; i < 200 && *port <= 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::ifstream(port_file) >> *port;
  }
  if (*port <= 0)
    return Internal("the supervisor did not start; see " + a.work_dir + "/fleet_supervisor.log");
  return supervisor;
}

void PrintSupervisorBench(const SupervisorBenchArgs& a, const nlohmann::json& out, double warmup_s,
                          size_t latency_samples) {
  const nlohmann::json& timeline = out["timeline"];
  std::printf(
      "fleet supervisor under %d vehicles (poses %.0f Hz, health 1 Hz), %.0f s after a %.0f s "
      "warm-up\n",
      a.vehicles, a.pose_hz, a.seconds, warmup_s);
  std::printf("%4s %12s %12s %10s %8s %8s\n", "s", "published", "received", "hist.queue", "cpu s",
              "rss MB");
  for (const nlohmann::json& row : timeline) {
    std::printf("%4d %12lld %12lld %10lld %8.2f %8.1f\n", row["s"].get<int>(),
                row["published"].get<long long>(), row["received"].get<long long>(),
                row["history_queue"].get<long long>(), row["cpu_s"].get<double>(),
                row["rss_mb"].get<double>());
  }
  std::printf(
      "received / published: %.3f\n",
      out["poses_received"].get<double>() / std::max(1.0, out["poses_published"].get<double>()));
  std::printf(
      "pose published -> in the live stream: p50 %.1f ms, p95 %.1f ms, p99 %.1f ms (%zu samples)\n",
      out["latency_ms"]["p50"].get<double>(), out["latency_ms"]["p95"].get<double>(),
      out["latency_ms"]["p99"].get<double>(), latency_samples);
  std::printf("supervisor: %.1f %% of one core, max RSS %.1f MB\n",
              out["supervisor_cpu_percent"].get<double>(),
              out["supervisor_rss_mb_max"].get<double>());
}

}  // namespace

Status RunSupervisorBench(const SupervisorBenchArgs& a) {
  int port = 0;
  auto supervisor = StartSupervisor(a, &port);
  if (!supervisor.ok()) return supervisor.status();
  std::atomic<bool> stop{false};
  std::atomic<long long> published{0};
  std::vector<double> latencies;
  std::mutex mutex;
  std::thread publisher(PublishFleet, std::cref(a), std::cref(stop), &published);
  std::thread reader(ReadStream, port, std::cref(stop), &latencies, &mutex);
  httplib::Client http("127.0.0.1", port);
  nlohmann::json timeline = nlohmann::json::array();
  auto [cpu0, rss0] = CpuAndRss(supervisor->pid());
  double max_rss = rss0;
  const double warmup_s = 3.0;
  for (int s = 1; s <= static_cast<int>(a.seconds + warmup_s); ++s) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    auto stats = http.Get("/api/stats");
    const nlohmann::json counters =
        stats ? nlohmann::json::parse(stats->body, nullptr, false) : nlohmann::json();
    auto [cpu, rss] = CpuAndRss(supervisor->pid());
    max_rss = std::max(max_rss, rss);
    timeline.push_back({{"s", s},
                        {"published", published.load()},
                        {"received", counters.value("poses_received", 0)},
                        {"history_queue", counters.value("history_queue", 0)},
                        {"cpu_s", cpu},
                        {"rss_mb", rss}});
    if (s == static_cast<int>(warmup_s)) {
      std::lock_guard lock(mutex);
      latencies.clear();
      cpu0 = cpu;
    }
  }
  stop = true;
  publisher.join();
  reader.join();
  const nlohmann::json& last = timeline.back();
  const nlohmann::json& first = timeline[static_cast<size_t>(warmup_s) - 1];
  const double cpu_pct = 100.0 * (last["cpu_s"].get<double>() - cpu0) / a.seconds;
  nlohmann::json out = {
      {"vehicles", a.vehicles},
      {"pose_hz", a.pose_hz},
      {"seconds", a.seconds},
      {"poses_published", last["published"].get<long long>() - first["published"].get<long long>()},
      {"poses_received", last["received"].get<long long>() - first["received"].get<long long>()},
      {"latency_samples", latencies.size()},
      {"latency_ms",
       {{"p50", replay::Percentile(latencies, 50)},
        {"p95", replay::Percentile(latencies, 95)},
        {"p99", replay::Percentile(latencies, 99)}}},
      {"supervisor_cpu_percent", cpu_pct},
      {"supervisor_rss_mb_max", max_rss},
      {"timeline", timeline}};
  PrintSupervisorBench(a, out, warmup_s, latencies.size());
  if (!a.json.empty()) std::ofstream(a.json) << out.dump(2) << "\n";
  if (supervisor->Stop(SIGTERM) != 0) return Internal("the supervisor did not stop cleanly");
  return Status::Ok();
}

}  // namespace fleetloc::bench
