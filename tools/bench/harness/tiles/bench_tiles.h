// fleetctl bench tiles: tile streaming from a real map_server process over loopback DDS —
// throughput next to ddsperf at the same sample size, and request→tile latency with 1, 10 and
// 50 requesting vehicles (one participant, one partition per vehicle) next to ddsperf ping-pong.
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "transport/participant.h"

namespace fleetloc::bench {

struct TileBenchSettings {
  std::string mosaic;  // empty: import the demo floor into work_dir
  std::string work_dir;
  int domain = 90;       // map server and clients; ddsperf uses domain + 1
  double seconds = 5.0;  // per phase, after a warm-up
  std::vector<int> vehicles{1, 10, 50};
  double rate_hz = 10.0;  // tile requests per vehicle per second (latency phase)
  int batch_tiles = 32;   // tiles per request in the throughput phase
  int pipeline = 2;       // requests in flight (2 × 32 tiles ≈ 3 MB: below rmem_max)
  std::string json;
  // Cyclone configurations of the map server, of the benchmark's participant and of the ddsperf
  // peer (empty: the built-in loopback one); secured ones measure DDS Security's cost, and a
  // smaller message size its cost (docs/benchmarks.md).
  std::string server_dds_config;
  std::string client_dds_config;
  std::string peer_dds_config;
};

Status RunTileBench(const TileBenchSettings& settings);

struct TileLatency {
  int vehicles = 0;
  long long requests = 0, answered = 0;
  double p50_ms = 0, p99_ms = 0, max_ms = 0;
};

// `vehicles` clients (vehicle ids "v<vehicles>-<i>") each ask the map server on `participant`'s
// domain for one random level-0 tile every 1 / settings.rate_hz s (staggered), for settings.seconds
// after a 1 s warm-up; the request → tile latency.
Result<TileLatency> MeasureTileLatency(const transport::Participant& participant, int vehicles,
                                       const TileBenchSettings& settings);

}  // namespace fleetloc::bench
