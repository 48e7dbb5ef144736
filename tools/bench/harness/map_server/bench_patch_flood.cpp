// fleetctl bench patch-flood: a real map_server process serving tiles to N vehicles (request →
// tile latency, as `bench tiles` measures it) first alone, then while one vehicle floods it with
// patches (1 MB of noise each, at --flood-mb-per-s); the mosaic file's size is sampled throughout,
// so it shows growth stopping at the flooding vehicle's quota. The server is configured with a
// high patch rate, so the quota is what stops the flood. No assertions: numbers for
// docs/benchmarks.md.
#include "harness/map_server/bench_patch_flood.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "harness/common/bench_paths.h"
#include "harness/tiles/bench_tiles.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_codec.h"
#include "runtime/child_process.h"
#include "transport/patch_client.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double FileMb(const std::string& path) {
  std::error_code ec;
  double bytes = 0;
  for (const char* suffix : {"", "-wal"}) {
    const auto size = fs::file_size(path + suffix, ec);
    if (!ec) bytes += static_cast<double>(size);
  }
  return bytes / (1 << 20);
}

// Sends 1 MB noise patches as vehicle "flood" at about `mb_per_s` until `stop`.
void Flood(const transport::Participant& participant, double mb_per_s,
           const std::atomic<bool>& stop, std::atomic<long long>* bytes_sent) {
  auto client = transport::PatchClient::Create(participant, "flood");
  if (!client.ok()) return spdlog::error("{}", client.status().message());
  while (!(*client)->ServerMatched() && !stop)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  cv::Mat noise(1024, 1024, CV_8UC1);
  cv::randu(noise, 0, 256);
  transport::PatchToSend patch;
  patch.pose = {0.5, 0.5, 0.0};
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(patch.covariance) =
      Eigen::Vector3d(1e-8, 1e-8, 1e-4).asDiagonal();
  patch.quality = 1.0f;
  patch.resolution_m = 0.0005;
  patch.png = *mosaic::EncodeTile(noise);
  const auto start = Clock::now();
  for (uint64_t sequence = 1; !stop; ++sequence) {
    patch.sequence = sequence;
    if ((*client)->Send(patch).ok()) *bytes_sent += static_cast<long long>(patch.png.size());
    const double due_s = static_cast<double>(*bytes_sent) / (mb_per_s * (1 << 20));
    std::this_thread::sleep_until(
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due_s)));
  }
}

nlohmann::json ToJson(const TileLatency& l) {
  return {{"vehicles", l.vehicles}, {"requests", l.requests}, {"answered", l.answered},
          {"p50_ms", l.p50_ms},     {"p99_ms", l.p99_ms},     {"max_ms", l.max_ms}};
}

// A fresh copy of the demo mosaic for the server to grow (its path), and the server's
// configuration beside it (map_server.json: a high patch rate, the quota).
Result<std::string> PrepareFloodMosaic(const PatchFloodBenchArgs& a) {
  fs::create_directories(a.tiles.work_dir);
  Result<std::string> demo =
      EnsureDemoMosaic(a.tiles.work_dir, "rock_dirt_2048.png", "flood_bench_demo.db");
  if (!demo.ok()) return demo.status();
  const std::string mosaic = a.tiles.work_dir + "/flood_bench.db",
                    config = a.tiles.work_dir + "/map_server.json";
  fs::remove(mosaic);
  fs::remove(mosaic + "-wal");
  fs::remove(mosaic + "-shm");
  fs::copy_file(*demo, mosaic);
  std::ofstream(config) << nlohmann::json{
      {"mosaic", mosaic},
      {"patch_intake",
       {{"patches_per_s", 1000},
        {"burst", 1000},
        {"max_mb_per_vehicle",
         a.quota_mb}}}}.dump();
  return mosaic;
}

void PrintFlood(const PatchFloodBenchArgs& a, int vehicles, const TileLatency& idle,
                const TileLatency& flooded, const nlohmann::json& out, double seconds,
                double stored_mb, double mb_before) {
  std::printf("tile request -> tile, %d vehicles at %.0f Hz each, %.0f s per phase\n", vehicles,
              a.tiles.rate_hz, a.tiles.seconds);
  std::printf("  alone:        p50 %6.2f ms  p99 %6.2f ms  max %6.2f ms  (%lld of %lld answered)\n",
              idle.p50_ms, idle.p99_ms, idle.max_ms, idle.answered, idle.requests);
  std::printf("  during flood: p50 %6.2f ms  p99 %6.2f ms  max %6.2f ms  (%lld of %lld answered)\n",
              flooded.p50_ms, flooded.p99_ms, flooded.max_ms, flooded.answered, flooded.requests);
  std::printf(
      "flood: %.0f MB sent in %.1f s (%.1f MB/s), %.1f MB stored (quota %d MB); mosaic file %.1f "
      "-> %.1f MB\n",
      out["flood_mb_sent"].get<double>(), seconds, out["flood_mb_per_s_sent"].get<double>(),
      stored_mb, a.quota_mb, mb_before, out["file_mb_after"].get<double>());
}

}  // namespace

Status RunPatchFloodBench(PatchFloodBenchArgs a) {
  Result<std::string> prepared = PrepareFloodMosaic(a);
  if (!prepared.ok()) return prepared.status();
  const std::string mosaic = *prepared, config = a.tiles.work_dir + "/map_server.json";
  auto server =
      runtime::ChildProcess::Start(runtime::ExecutableDir() + "/map_server",
                                   {"--config", config, "--domain", std::to_string(a.tiles.domain)},
                                   a.tiles.work_dir + "/map_server.log");
  if (!server.ok()) return server.status();
  auto participant = transport::Participant::Create(a.tiles.domain);
  if (!participant.ok()) return participant.status();
  const int vehicles = a.tiles.vehicles.empty() ? 10 : a.tiles.vehicles.front();
  spdlog::info("bench patch-flood: tiles for {} vehicles, alone", vehicles);
  Result<TileLatency> idle = MeasureTileLatency(*participant, vehicles, a.tiles);
  if (!idle.ok()) return idle.status();
  const double mb_before = FileMb(mosaic);
  std::atomic<bool> stop{false};
  std::atomic<long long> sent{0};
  nlohmann::json growth = nlohmann::json::array();
  std::thread flood(Flood, std::cref(*participant), a.flood_mb_per_s, std::cref(stop), &sent);
  std::thread sampler([&] {
    for (const auto start = Clock::now(); !stop;
         std::this_thread::sleep_for(std::chrono::milliseconds(500))) {
      growth.push_back({{"t_s", std::chrono::duration<double>(Clock::now() - start).count()},
                        {"sent_mb", static_cast<double>(sent) / (1 << 20)},
                        {"file_mb", FileMb(mosaic)}});
    }
  });
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the flood is under way
  spdlog::info("bench patch-flood: tiles for {} vehicles, during a {:.0f} MB/s patch flood",
               vehicles, a.flood_mb_per_s);
  Result<TileLatency> flooded = MeasureTileLatency(*participant, vehicles, a.tiles);
  stop = true;
  flood.join();
  sampler.join();
  if (!flooded.ok()) return flooded.status();
  const double seconds = growth.empty() ? 1.0 : growth.back()["t_s"].get<double>();
  (void)server->Stop(SIGTERM);
  auto store = mosaic::PatchStore::Open(mosaic);
  if (!store.ok()) return store.status();
  auto usage = (*store)->UsageByVehicle();
  const double stored_mb = usage.ok() && usage->count("flood")
                               ? static_cast<double>(usage->at("flood").bytes) / (1 << 20)
                               : 0;
  const nlohmann::json out = {
      {"alone", ToJson(*idle)},
      {"during_flood", ToJson(*flooded)},
      {"flood_mb_per_s_target", a.flood_mb_per_s},
      {"flood_mb_sent", static_cast<double>(sent) / (1 << 20)},
      {"flood_mb_per_s_sent", static_cast<double>(sent) / (1 << 20) / seconds},
      {"quota_mb", a.quota_mb},
      {"flood_mb_stored", stored_mb},
      {"file_mb_before", mb_before},
      {"file_mb_after", FileMb(mosaic)},
      {"growth", growth}};
  PrintFlood(a, vehicles, *idle, *flooded, out, seconds, stored_mb, mb_before);
  if (!a.json.empty()) std::ofstream(a.json) << out.dump(2) << "\n";
  return Status::Ok();
}

}  // namespace fleetloc::bench
