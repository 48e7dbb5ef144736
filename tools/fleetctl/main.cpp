// fleetctl: one CLI with git-style subcommands (docs/formats.md).
#include <malloc.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <iostream>

#include "cli/command_line.h"
#include "commands.h"

int main(int argc, char** argv) {
  // Reuse freed heap instead of handing it back to the kernel and faulting it in again (a page
  // fault costs ~10 us on the project's VM): every tile an import encodes allocates and frees
  // ~300 KB of zlib state, which cost a third of a gigapixel import (docs/benchmarks.md, "Mosaic
  // store at scale"). Setting the trim threshold turns off glibc's adaptive mmap threshold, so
  // that is fixed too, else every 700x560 block a MosaicView assembles (392 KB) is a fresh mmap.
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // the largest glibc allows; the default is 128 KiB
  CLI::App app{"fleetloc maintenance and offline tools"};
  app.require_subcommand(1);
  fleetloc::Status result;
  fleetloc::fleetctl::RegisterMosaicCommands(app, &result);
  fleetloc::fleetctl::RegisterSimCommand(app, &result);
  fleetloc::fleetctl::RegisterSimForwardCommand(app, &result);
  fleetloc::fleetctl::RegisterTrackCommand(app, &result);
  fleetloc::fleetctl::RegisterBenchCommand(app, &result);
  fleetloc::fleetctl::RegisterComposeCommand(app, &result);
  fleetloc::fleetctl::RegisterRemapCommand(app, &result);
  fleetloc::fleetctl::RegisterCalibrateCommand(app, &result);
  fleetloc::fleetctl::RegisterMapmatchCommand(app, &result);
  fleetloc::fleetctl::RegisterRelocCommand(app, &result);
  fleetloc::fleetctl::RegisterStatusCommand(app, &result);
  spdlog::set_default_logger(spdlog::stderr_color_mt("fleetctl"));
  try {
    if (auto exit_status = fleetloc::cli::ParseCommandLine(app, "fleetctl", argc, argv))
      return *exit_status;
  } catch (const std::exception& e) {
    std::cerr << "fleetctl: " << e.what() << "\n";
    return 1;
  }
  if (!result.ok()) std::cerr << "fleetctl: " << result.message() << "\n";
  return result.ExitCode();
}
