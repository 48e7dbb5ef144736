// `fleetctl bench patch-flood`: its options;
// the run is bench::RunPatchFloodBench (tools/bench/harness/map_server).
#include <filesystem>
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/map_server/bench_patch_flood.h"

namespace fleetloc::fleetctl {

void RegisterBenchPatchFloodCommand(CLI::App& bench, Status* result) {
  auto a = std::make_shared<bench::PatchFloodBenchArgs>();
  a->tiles.work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench-flood").string();
  a->tiles.domain = 92;
  a->tiles.seconds = 10;
  a->tiles.vehicles = {10};
  CLI::App* cmd = bench.add_subcommand(
      "patch-flood",
      "Tile latency for other vehicles while one floods the map server with patches; disk growth");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--vehicles", a->tiles.vehicles.front(), "Vehicles asking for tiles")
      ->check(CLI::Range(1, 500));
  cmd->add_option("--rate-hz", a->tiles.rate_hz, "Tile requests per vehicle per second")
      ->check(CLI::Range(0.1, 1000.0));
  cmd->add_option("--seconds", a->tiles.seconds, "Measured seconds per phase")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->add_option("--flood-mb-per-s", a->flood_mb_per_s,
                  "Patch bytes per second the flooding vehicle sends")
      ->check(CLI::Range(0.1, 10000.0));
  cmd->add_option("--quota-mb", a->quota_mb,
                  "The flooding vehicle's quota (patch_intake.max_mb_per_vehicle)")
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--domain", a->tiles.domain, "DDS domain")->check(CLI::Range(0, 232));
  cmd->add_option("--work-dir", a->tiles.work_dir, "Directory for the mosaic and logs");
  cmd->add_option("--json", a->json, "Write every number as JSON");
  cmd->callback([a, result] { *result = bench::RunPatchFloodBench(*a); });
}

}  // namespace fleetloc::fleetctl
