// fleetctl subcommand registration, one scheme for every command:
// Register<Name>Command(s)(CLI::App& parent, Status* result), defined in <name>_command(s).cpp,
// adds its subcommand(s) to the parent; a subcommand's callback stores its outcome in *result (main
// turns it into the exit status of docs/cli.md). The `bench` subcommands are declared in
// bench/bench_commands.h.
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

// `mosaic vehicles`, `mosaic prune` and `mosaic rollback` (mosaic_upkeep_commands.cpp), added to
// `mosaic` by RegisterMosaicCommands.
void RegisterMosaicUpkeepCommands(CLI::App& mosaic, Status* result);

}  // namespace fleetloc::fleetctl
