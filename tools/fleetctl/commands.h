// fleetctl subcommand registration. Each Register* adds its subcommands to the app; a subcommand's
// callback stores its outcome in *result (main turns it into the exit status of docs/cli.md).
#pragma once

#include <CLI/CLI.hpp>

#include "base/status.h"

namespace fleetloc::fleetctl {

void RegisterMosaicCommands(CLI::App& app, Status* result);
void RegisterSimCommand(CLI::App& app, Status* result);
void RegisterSimForwardCommand(CLI::App& app, Status* result);
void RegisterTrackCommand(CLI::App& app, Status* result);
void RegisterBenchCommand(CLI::App& app, Status* result);
void RegisterComposeCommand(CLI::App& app, Status* result);
void RegisterRemapCommand(CLI::App& app, Status* result);
void RegisterCalibrateCommand(CLI::App& app, Status* result);
void RegisterMapmatchCommand(CLI::App& app, Status* result);
void RegisterRelocCommand(CLI::App& app, Status* result);
void RegisterStatusCommand(CLI::App& app, Status* result);

// `mosaic vehicles` and `mosaic prune` (mosaic_upkeep_commands.cpp), added by
// RegisterMosaicCommands.
void AddMosaicUpkeepCommands(CLI::App& mosaic, Status* result);
// `bench mosaic`, added to the `bench` subcommand by RegisterBenchCommand.
void AddBenchMosaicCommand(CLI::App& bench, Status* result);
// `bench reloc` (bench_reloc_command.cpp).
void RegisterBenchReloc(CLI::App& bench, Status* result);
void RegisterBenchDenseProbe(CLI::App& bench, Status* result);
void RegisterBenchStress(CLI::App& bench, Status* result);
// `bench supervisor` (bench_supervisor.cpp).
void RegisterBenchSupervisor(CLI::App& bench, Status* result);
// `bench remap` (bench_remap.cpp) and `bench patch-flood` (bench_patch_flood.cpp).
void RegisterBenchRemap(CLI::App& bench, Status* result);
void RegisterBenchPatchFlood(CLI::App& bench, Status* result);
// `bench supervisor-abuse` (bench_supervisor_abuse.cpp).
void RegisterBenchSupervisorAbuse(CLI::App& bench, Status* result);

}  // namespace fleetloc::fleetctl
