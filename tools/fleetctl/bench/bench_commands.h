// `fleetctl bench ...` registration: one Register<Name>Command per benchmark, each in
// bench_<name>_command.cpp, adding its subcommand and options to `bench`. The benchmarks
// themselves are the harness library, tools/bench/harness/.
#pragma once

#include <CLI/CLI.hpp>

#include "base/status.h"

namespace fleetloc::fleetctl {

void RegisterBenchTrackerCommand(CLI::App& bench, Status* result);
void RegisterBenchTrackerStressCommand(CLI::App& bench, Status* result);
void RegisterBenchTilesCommand(CLI::App& bench, Status* result);
void RegisterBenchAgentCommand(CLI::App& bench, Status* result);
void RegisterBenchMosaicCommand(CLI::App& bench, Status* result);
void RegisterBenchMosaicBuildCommand(CLI::App& bench, Status* result);
void RegisterBenchMosaicDistortionCommand(CLI::App& bench, Status* result);
void RegisterBenchMapfitCommand(CLI::App& bench, Status* result);
void RegisterBenchRelocCommand(CLI::App& bench, Status* result);
void RegisterBenchDenseProbeCommand(CLI::App& bench, Status* result);
void RegisterBenchSupervisorCommand(CLI::App& bench, Status* result);
void RegisterBenchSupervisorAbuseCommand(CLI::App& bench, Status* result);
void RegisterBenchRemapCommand(CLI::App& bench, Status* result);
void RegisterBenchPatchFloodCommand(CLI::App& bench, Status* result);

// `--timing-replays N` (1–20) into `replays`: the tracker benchmarks' replays of fleetloc per run,
// each frame's time the least of them (bench::BenchSettings::timing_replays).
void AddTimingReplaysOption(CLI::App* command, int* replays);

}  // namespace fleetloc::fleetctl
