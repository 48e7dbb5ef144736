// Tile streaming benchmark against a real map_server process (see bench_tiles.h).
#include "harness/tiles/bench_tiles.h"

#include <spdlog/spdlog.h>

#include <csignal>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "harness/common/bench_paths.h"
#include "harness/tiles/ddsperf_peer.h"
#include "io/file_util.h"
#include "mosaic/importer.h"
#include "replay/replay.h"
#include "runtime/child_process.h"
#include "transport/tile_client.h"
#include "transport/waitset.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using transport::TileClient;

double SecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Waits until `client` sees the server and the server has opened its reply channel.
Result<fleetloc_MosaicInfo> Connect(TileClient& client) {
  const auto start = Clock::now();
  std::optional<fleetloc_MosaicInfo> info;
  while (SecondsSince(start) < 30) {
    if (!info) info = client.LatestMosaicInfo();
    if (info && client.RequestsMatched()) return *info;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return Internal("bench tiles: no map server answered on the domain within 30 s");
}

std::vector<mosaic::TileKey> LevelZeroKeys(const fleetloc_MosaicInfo& info) {
  std::vector<mosaic::TileKey> keys;
  for (int r = 0; r * info.tile_size_px < info.height_px; ++r) {
    for (int c = 0; c * info.tile_size_px < info.width_px; ++c) keys.push_back({0, c, r});
  }
  return keys;
}

struct Throughput {
  double tiles_per_s = 0, megabytes_per_s = 0, mean_tile_bytes = 0;
  long long tiles = 0;
};

// Keeps `pipeline` requests of `batch` tiles in flight for `seconds` after a 1 s warm-up.
Result<Throughput> MeasureThroughput(const transport::Participant& participant,
                                     const TileBenchSettings& s) {
  auto client = TileClient::Create(participant, "tput-0");
  if (!client.ok()) return client.status();
  Result<fleetloc_MosaicInfo> info = Connect(**client);
  if (!info.ok()) return info.status();
  const std::vector<mosaic::TileKey> keys = LevelZeroKeys(*info);
  auto waitset = transport::WaitSet::Create(participant);
  if (!waitset.ok()) return waitset.status();
  FLEETLOC_RETURN_IF_ERROR(waitset->AttachReader((*client)->tile_reader(), 1));
  std::map<uint32_t, int> outstanding;  // request id → tiles still to come
  uint32_t next_id = 1;
  size_t next_key = 0;
  auto send = [&]() -> Status {
    std::vector<mosaic::TileKey> batch;
    batch.reserve(s.batch_tiles);
    for (int i = 0; i < s.batch_tiles; ++i) batch.push_back(keys[next_key++ % keys.size()]);
    outstanding[next_id] = s.batch_tiles;
    return (*client)->Request(next_id++, "", batch);
  };
  Throughput t;
  long long bytes = 0;
  const auto start = Clock::now();
  Clock::time_point measuring;
  bool warm = false;
  while (SecondsSince(start) < 1.0 + s.seconds) {
    if (!warm && SecondsSince(start) >= 1.0) {
      warm = true;
      measuring = Clock::now();
      t.tiles = 0;
      bytes = 0;
    }
    while (static_cast<int>(outstanding.size()) < s.pipeline) FLEETLOC_RETURN_IF_ERROR(send());
    (void)waitset->Wait(0.01);
    auto tiles = (*client)->TakeTiles();
    if (!tiles.ok()) return tiles.status();
    for (const auto& tile : *tiles) {
      ++t.tiles;
      bytes += static_cast<long long>(tile.data.size());
      if (--outstanding[tile.request_id] == 0) outstanding.erase(tile.request_id);
    }
  }
  const double elapsed = SecondsSince(measuring);
  t.tiles_per_s = t.tiles / elapsed;
  t.megabytes_per_s = bytes / elapsed / 1e6;
  t.mean_tile_bytes = t.tiles > 0 ? static_cast<double>(bytes) / t.tiles : 0;
  return t;
}

}  // namespace

Result<TileLatency> MeasureTileLatency(const transport::Participant& participant, int vehicles,
                                       const TileBenchSettings& s) {
  std::vector<std::unique_ptr<TileClient>> fleet;
  auto waitset = transport::WaitSet::Create(participant);
  if (!waitset.ok()) return waitset.status();
  for (int i = 0; i < vehicles; ++i) {
    auto client = TileClient::Create(participant, fmt::format("v{}-{}", vehicles, i));
    if (!client.ok()) return client.status();
    FLEETLOC_RETURN_IF_ERROR(waitset->AttachReader((*client)->tile_reader(), i));
    fleet.push_back(std::move(client).value());
  }
  Result<fleetloc_MosaicInfo> info = Connect(*fleet[0]);
  if (!info.ok()) return info.status();
  const std::vector<mosaic::TileKey> keys = LevelZeroKeys(*info);
  std::mt19937 rng(7);
  std::map<std::pair<int, uint32_t>, Clock::time_point> sent;
  std::vector<double> latencies_ms;
  std::vector<Clock::time_point> due(vehicles);
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / s.rate_hz));
  const auto start = Clock::now() + std::chrono::seconds(1);  // warm-up: channels opened first
  for (int i = 0; i < vehicles; ++i) {
    FLEETLOC_RETURN_IF_ERROR(fleet[i]->Request(0, "", {keys[0]}));  // opens the reply channel
    due[i] = start + period * i / vehicles;
  }
  uint32_t next_id = 1;
  TileLatency result{vehicles};
  while (Clock::now() < start + std::chrono::duration<double>(s.seconds)) {
    for (int i = 0; i < vehicles; ++i) {
      if (Clock::now() < due[i]) continue;
      const uint32_t id = next_id++;
      sent[{i, id}] = Clock::now();
      FLEETLOC_RETURN_IF_ERROR(fleet[i]->Request(id, "", {keys[rng() % keys.size()]}));
      ++result.requests;
      due[i] += period;
    }
    (void)waitset->Wait(0.001);
    for (int i = 0; i < vehicles; ++i) {
      auto tiles = fleet[i]->TakeTiles();
      if (!tiles.ok()) return tiles.status();
      for (const auto& tile : *tiles) {
        const auto it = sent.find({i, tile.request_id});
        if (it == sent.end()) continue;  // warm-up request
        latencies_ms.push_back(
            std::chrono::duration<double, std::milli>(Clock::now() - it->second).count());
        sent.erase(it);
      }
    }
  }
  result.answered = static_cast<long long>(latencies_ms.size());
  result.p50_ms = replay::Percentile(latencies_ms, 50);
  result.p99_ms = replay::Percentile(latencies_ms, 99);
  result.max_ms = replay::Percentile(latencies_ms, 100);
  return result;
}

namespace {

void Print(const Throughput& tp, const DdsperfThroughput& peer, const std::vector<TileLatency>& lat,
           const DdsperfLatency& ping) {
  std::printf(
      "\ntile streaming, loopback, one map_server process (throughput phase: one vehicle)\n");
  std::printf("%-28s %12s %10s %12s\n", "method", "samples/s", "MB/s", "sample bytes");
  std::printf("%-28s %12.0f %10.1f %12.0f\n", "fleetloc tiles (req/reply)", tp.tiles_per_s,
              tp.megabytes_per_s, tp.mean_tile_bytes);
  std::printf("%-28s %12.0f %10.1f %12.0f\n", "ddsperf pub/sub", peer.samples_per_s,
              peer.megabytes_per_s, tp.mean_tile_bytes);
  std::printf("fleetloc / ddsperf throughput: %.2f\n", tp.megabytes_per_s / peer.megabytes_per_s);
  std::printf("\nrequest -> tile latency (one %0.f-byte tile per request)\n", tp.mean_tile_bytes);
  std::printf("%-10s %10s %10s %10s %10s %10s\n", "vehicles", "requests", "answered", "p50 ms",
              "p99 ms", "max ms");
  for (const TileLatency& l : lat) {
    std::printf("%-10d %10lld %10lld %10.3f %10.3f %10.3f\n", l.vehicles, l.requests, l.answered,
                l.p50_ms, l.p99_ms, l.max_ms);
  }
  std::printf("ddsperf ping-pong round trip at that size: p50 %.3f ms, p99 %.3f ms\n",
              ping.rtt_p50_us / 1e3, ping.rtt_p99_us / 1e3);
}

nlohmann::json ToJson(const TileBenchSettings& s, const Throughput& tp,
                      const DdsperfThroughput& peer, const std::vector<TileLatency>& lat,
                      const DdsperfLatency& ping) {
  nlohmann::json latency = nlohmann::json::array();
  for (const TileLatency& l : lat) {
    latency.push_back({{"vehicles", l.vehicles},
                       {"requests", l.requests},
                       {"answered", l.answered},
                       {"p50_ms", l.p50_ms},
                       {"p99_ms", l.p99_ms},
                       {"max_ms", l.max_ms}});
  }
  return {{"settings",
           {{"seconds", s.seconds},
            {"rate_hz", s.rate_hz},
            {"batch_tiles", s.batch_tiles},
            {"pipeline", s.pipeline}}},
          {"throughput",
           {{"tiles_per_s", tp.tiles_per_s},
            {"megabytes_per_s", tp.megabytes_per_s},
            {"mean_tile_bytes", tp.mean_tile_bytes}}},
          {"ddsperf_throughput",
           {{"samples_per_s", peer.samples_per_s}, {"megabytes_per_s", peer.megabytes_per_s}}},
          {"throughput_ratio", tp.megabytes_per_s / peer.megabytes_per_s},
          {"latency", latency},
          {"ddsperf_pingpong", {{"rtt_p50_us", ping.rtt_p50_us}, {"rtt_p99_us", ping.rtt_p99_us}}}};
}

}  // namespace

Status RunTileBench(const TileBenchSettings& s) {
  const std::string work = io::AbsoluteDir(s.work_dir).string();
  std::error_code error;
  fs::create_directories(work, error);
  if (error) return InvalidInput(work + ": cannot create the work directory: " + error.message());
  Result<std::string> mosaic =
      s.mosaic.empty() ? EnsureDemoMosaic(work, "rock_dirt_2048.png", "tiles_bench_mosaic.db")
                       : Result<std::string>(s.mosaic);
  if (!mosaic.ok()) return mosaic.status();
  const std::string config = work + "/cyclonedds.xml";
  FLEETLOC_RETURN_IF_ERROR(io::WriteFileAtomically(config, transport::DefaultLoopbackXml()));
  const std::string uri =
      "file://" + (s.peer_dds_config.empty() ? config : fs::absolute(s.peer_dds_config).string());
  auto server = runtime::ChildProcess::Start(
      runtime::ExecutableDir() + "/map_server",
      {"--mosaic", *mosaic, "--domain", std::to_string(s.domain), "--server-id", "bench",
       "--dds-config", s.server_dds_config.empty() ? config : s.server_dds_config},
      work + "/map_server.log");
  if (!server.ok()) return server.status();
  auto participant = transport::Participant::Create(
      s.domain, {"", s.client_dds_config.empty() ? config : s.client_dds_config});
  if (!participant.ok()) return participant.status();
  spdlog::info("bench tiles: throughput for {} s", s.seconds);
  Result<Throughput> tp = MeasureThroughput(*participant, s);
  if (!tp.ok()) return tp.status();
  std::vector<TileLatency> latencies;
  for (int n : s.vehicles) {
    spdlog::info("bench tiles: latency with {} vehicles for {} s", n, s.seconds);
    Result<TileLatency> l = MeasureTileLatency(*participant, n, s);
    if (!l.ok()) return l.status();
    latencies.push_back(*l);
  }
  server->Stop(SIGTERM);
  const int size = static_cast<int>(tp->mean_tile_bytes);
  spdlog::info("bench tiles: ddsperf pub/sub and ping-pong at {} bytes", size);
  Result<DdsperfThroughput> peer = RunDdsperfThroughput(s.domain + 1, size, s.seconds, uri, work);
  if (!peer.ok()) return peer.status();
  Result<DdsperfLatency> ping = RunDdsperfPingPong(s.domain + 1, size, s.seconds, uri, work);
  if (!ping.ok()) return ping.status();
  Print(*tp, *peer, latencies, *ping);
  if (s.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(s.json, ToJson(s, *tp, *peer, latencies, *ping).dump(2) + "\n");
}

}  // namespace fleetloc::bench
