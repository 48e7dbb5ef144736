// Live agent vs offline tracker, same run, side by side.
#include "harness/agent/bench_agent.h"

#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/common/bench_paths.h"
#include "io/file_util.h"
#include "replay/replay.h"
#include "runtime/child_process.h"
#include "support/tracker_summary.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

// Runs a sibling program to completion; InvalidInput naming it and its log if it fails.
Status RunSibling(const std::string& program, const std::vector<std::string>& args,
                  const std::string& log, std::chrono::seconds limit) {
  auto child = runtime::ChildProcess::Start(runtime::ExecutableDir() + "/" + program, args, log);
  if (!child.ok()) return child.status();
  const int status = child->Wait(limit);
  if (status != 0)
    return Internal(program + " failed (exit " + std::to_string(status) + "), see " + log);
  return Status::Ok();
}

}  // namespace

Status RunAgentBench(const AgentBenchSettings& s) {
  const std::string work = io::AbsoluteDir(s.work_dir).string();
  fs::create_directories(work);
  Result<std::string> mosaic =
      EnsureDemoMosaic(work, "rock_dirt_2048.png", "agent_bench_mosaic.db");
  if (!mosaic.ok()) return mosaic.status();
  const std::string run_dir = work + "/run";
  spdlog::info("bench agent: simulating {} frames", s.frames);
  FLEETLOC_RETURN_IF_ERROR(RunSibling("fleetctl",
                                      {"sim", "--mosaic", *mosaic, "--frames",
                                       std::to_string(s.frames), "--out", run_dir, "--overwrite"},
                                      work + "/sim.log", std::chrono::seconds(1800)));
  Result<run_io::Run> run = run_io::ReadRun(run_dir);
  if (!run.ok()) return run.status();
  spdlog::info("bench agent: offline tracker");
  Result<replay::ReplayResult> offline = fleetctl::TrackOffline(*mosaic, *run, {}, 256);
  if (!offline.ok()) return offline.status();
  spdlog::info("bench agent: map_server and tracker_agent (fast replay) on domain {}", s.domain);
  auto server = runtime::ChildProcess::Start(
      runtime::ExecutableDir() + "/map_server",
      {"--mosaic", *mosaic, "--domain", std::to_string(s.domain)}, work + "/map_server.log");
  if (!server.ok()) return server.status();
  const std::string summary_path = work + "/agent_summary.json";
  fs::remove(summary_path);
  fs::remove(work + "/outbox.db");
  FLEETLOC_RETURN_IF_ERROR(
      RunSibling("tracker_agent",
                 {"--run", run_dir, "--domain", std::to_string(s.domain), "--fast", "--vehicle-id",
                  "bench", "--outbox", work + "/outbox.db", "--summary", summary_path},
                 work + "/agent.log", std::chrono::seconds(3600)));
  server->Stop(SIGTERM);
  Result<std::string> text = io::ReadFileText(summary_path);
  if (!text.ok()) return text.status();
  const nlohmann::json agent = nlohmann::json::parse(*text);
  const double offline_median = replay::Percentile(offline->cycle_ms, 50);
  const double offline_p95 = replay::Percentile(offline->cycle_ms, 95);
  const double live_median = agent["cycle_ms"]["median"], live_p95 = agent["cycle_ms"]["p95"];
  const double ratio = live_median / offline_median;
  std::printf("\ntracker cycle, same run of %d frames (rock floor, 640x480, 5 Hz at 3000 px/s)\n",
              s.frames);
  std::printf("%-34s %8s %10s %10s\n", "path", "frames", "median ms", "p95 ms");
  std::printf("%-34s %8zu %10.3f %10.3f\n", "offline (fleetctl track replay)",
              offline->poses.size(), offline_median, offline_p95);
  std::printf("%-34s %8lld %10.3f %10.3f\n", "live (tracker_agent over DDS)",
              agent["frames"].get<long long>(), live_median, live_p95);
  std::printf("live / offline median: %.3f -> %s\n", ratio,
              ratio <= 1.10 ? "within 10 %" : "NOT within 10 %");
  std::printf("agent tiles: %s\n", agent["tiles"].dump().c_str());
  if (s.json.empty()) return Status::Ok();
  const nlohmann::json out{{"frames", s.frames},
                           {"offline", {{"median_ms", offline_median}, {"p95_ms", offline_p95}}},
                           {"live", agent},
                           {"ratio", ratio}};
  return io::WriteFileAtomically(s.json, out.dump(2) + "\n");
}

}  // namespace fleetloc::bench
