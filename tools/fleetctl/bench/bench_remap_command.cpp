// `fleetctl bench remap`: its options;
// the run is bench::RunRemapBench (tools/bench/harness/map_server).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/map_server/bench_remap.h"

namespace fleetloc::fleetctl {

void RegisterBenchRemapCommand(CLI::App& bench, Status* result) {
  auto a = std::make_shared<bench::RemapBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "remap", "A re-mapping job over many stored patches: time and peak memory");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--patches", a->patches, "Patches stored before the job")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--work-dir", a->work_dir, "Directory for the mosaic");
  cmd->add_option("--json", a->json, "Write every number as JSON");
  cmd->callback([a, result] { *result = bench::RunRemapBench(*a); });
}

}  // namespace fleetloc::fleetctl
