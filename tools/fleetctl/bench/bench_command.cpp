// `fleetctl bench`: the parent of every benchmark subcommand (bench_commands.h), in the order
// `fleetctl bench --help` lists them.
#include "bench/bench_commands.h"
#include "commands.h"

namespace fleetloc::fleetctl {

void RegisterBenchCommand(CLI::App& app, Status* result) {
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks");
  bench->require_subcommand(1);
  RegisterBenchTrackerCommand(*bench, result);
  RegisterBenchTilesCommand(*bench, result);
  RegisterBenchAgentCommand(*bench, result);
  RegisterBenchMosaicCommand(*bench, result);
  RegisterBenchMosaicBuildCommand(*bench, result);
  RegisterBenchMosaicDistortionCommand(*bench, result);
  RegisterBenchMapfitCommand(*bench, result);
  RegisterBenchRelocCommand(*bench, result);
  RegisterBenchDenseProbeCommand(*bench, result);
  RegisterBenchTrackerStressCommand(*bench, result);
  RegisterBenchSupervisorCommand(*bench, result);
  RegisterBenchSupervisorAbuseCommand(*bench, result);
  RegisterBenchRemapCommand(*bench, result);
  RegisterBenchPatchFloodCommand(*bench, result);
}

}  // namespace fleetloc::fleetctl
