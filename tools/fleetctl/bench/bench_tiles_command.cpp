// `fleetctl bench tiles`: its options; the run is bench::RunTileBench (tools/bench/harness/tiles).
#include <filesystem>
#include <memory>

#include "bench/bench_commands.h"
#include "harness/tiles/bench_tiles.h"

namespace fleetloc::fleetctl {

void RegisterBenchTilesCommand(CLI::App& bench, Status* result) {
  auto s = std::make_shared<bench::TileBenchSettings>();
  s->work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench-tiles").string();
  CLI::App* tiles = bench.add_subcommand(
      "tiles", "Tile streaming from a map_server process: throughput and latency vs ddsperf");
  tiles->option_defaults()->always_capture_default();
  tiles->add_option("--mosaic", s->mosaic, "Mosaic to serve (default: import the demo rock floor)");
  tiles->add_option("--work-dir", s->work_dir, "Logs, configuration and the imported mosaic");
  tiles->add_option("--domain", s->domain, "DDS domain (ddsperf uses the next one)")
      ->check(CLI::Range(0, 231));
  tiles->add_option("--seconds", s->seconds, "Duration of each phase")
      ->check(CLI::Range(1.0, 600.0));
  tiles->add_option("--vehicles", s->vehicles, "Vehicle counts of the latency phases")
      ->delimiter(',')
      ->check(CLI::Range(1, 500));
  tiles->add_option("--rate-hz", s->rate_hz, "Tile requests per vehicle per second")
      ->check(CLI::Range(0.1, 1000.0));
  tiles->add_option("--batch", s->batch_tiles, "Tiles per request (throughput)")
      ->check(CLI::Range(1, 256));
  tiles->add_option("--pipeline", s->pipeline, "Requests in flight (throughput)")
      ->check(CLI::Range(1, 64));
  tiles->add_option("--json", s->json, "Write every number to this JSON file");
  tiles->add_option("--server-dds-config", s->server_dds_config,
                    "Cyclone DDS XML of the map server (default: built-in loopback)");
  tiles->add_option("--client-dds-config", s->client_dds_config,
                    "Cyclone DDS XML of the requesting participant (default: built-in loopback)");
  tiles->add_option("--peer-dds-config", s->peer_dds_config,
                    "Cyclone DDS XML of the ddsperf peer (default: built-in loopback)");
  tiles->callback([s, result] { *result = bench::RunTileBench(*s); });
}

}  // namespace fleetloc::fleetctl
