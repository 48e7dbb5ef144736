// fleetctl: one CLI with git-style subcommands (CONTRACT section 6).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <iostream>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"fleetloc maintenance and offline tools"};
  app.require_subcommand(1);
  fleetloc::Status result;
  fleetloc::fleetctl::RegisterMosaicCommands(app, &result);
  fleetloc::fleetctl::RegisterSimCommand(app, &result);
  fleetloc::fleetctl::RegisterTrackCommand(app, &result);
  fleetloc::fleetctl::RegisterBenchCommand(app, &result);
  fleetloc::fleetctl::RegisterComposeCommand(app, &result);
  fleetloc::fleetctl::RegisterRemapCommand(app, &result);
  fleetloc::fleetctl::RegisterCalibrateCommand(app, &result);
  spdlog::set_default_logger(spdlog::stderr_color_mt("fleetctl"));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::cerr << "fleetctl: " << e.what() << "\n";
    return 1;
  }
  if (!result.ok()) std::cerr << "fleetctl: " << result.message() << "\n";
  return result.ExitCode();
}
