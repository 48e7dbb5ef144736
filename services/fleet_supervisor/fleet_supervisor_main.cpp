// fleet_supervisor: the operators' view of the fleet (DDS in, HTTP dashboard out) until
// SIGINT/SIGTERM.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "cli/command_line.h"
#include "fleet_supervisor/fleet_supervisor.h"
#include "runtime/logging.h"
#include "runtime/stop_signal.h"

namespace {

int SupervisorMain(int argc, char** argv) {
  using namespace fleetloc::fleet_supervisor;
  CLI::App app{
      "fleetloc fleet supervisor: fleet state, alerts, history and the operators' dashboard"};
  std::string config_path, history, dds_config, bind, token_file, web_dir, port_file;
  std::string metrics_port_file;
  int domain = -1, port = -1, metrics_port = -1;
  app.add_option("--config", config_path, "Configuration (JSON; defaults for absent keys)");
  app.add_option("--domain", domain, "DDS domain id (overrides the configuration)");
  app.add_option("--dds-config", dds_config, "Cyclone DDS XML (default: built-in loopback)");
  app.add_option("--history", history, "SQLite history file (overrides the configuration)");
  app.add_option("--http-bind", bind, "Address to listen on (default 127.0.0.1)");
  app.add_option("--http-port", port, "Port (0: any free one; see --port-file)");
  app.add_option("--port-file", port_file, "Write the bound port into this file");
  app.add_option("--token-file", token_file, "File whose first line is the maintainer token");
  app.add_option("--metrics-port", metrics_port,
                 "Prometheus /metrics port (0: any free one; default 9472)");
  app.add_option("--metrics-port-file", metrics_port_file,
                 "Write the bound metrics port into this file");
  app.add_option("--web-dir", web_dir, "Dashboard files (default: installed beside the binary)");
  if (auto exit_status = fleetloc::cli::ParseCommandLine(app, "fleet_supervisor", argc, argv))
    return *exit_status;

  SupervisorConfig config;
  if (!config_path.empty()) {
    auto loaded = LoadSupervisorConfig(config_path);
    if (!loaded.ok()) {
      std::fprintf(stderr, "fleet_supervisor: %s\n", loaded.status().message().c_str());
      return 2;
    }
    config = *loaded;
  }
  if (domain >= 0) config.domain_id = domain;
  if (!dds_config.empty()) config.dds_config_path = dds_config;
  if (!history.empty()) config.history_db = history;
  if (!bind.empty()) config.http_bind = bind;
  if (port >= 0) config.http_port = port;
  if (!port_file.empty()) config.port_file = port_file;
  if (!token_file.empty()) {
    config.maintainer_token = "";
    config.maintainer_token_file = token_file;
  }
  if (!web_dir.empty()) config.web_dir = web_dir;
  if (metrics_port >= 0) config.metrics.port = metrics_port;
  if (!metrics_port_file.empty()) config.metrics.port_file = metrics_port_file;
  fleetloc::runtime::SetupLogging(config.supervisor_id);
  const std::atomic<bool>& stop = fleetloc::runtime::InstallStopSignals();
  auto supervisor = FleetSupervisor::Create(config);
  if (!supervisor.ok()) {
    spdlog::error("{}", supervisor.status().message());
    return supervisor.status().ExitCode();
  }
  const fleetloc::Status ran = (*supervisor)->Run(stop);
  if (!ran.ok()) spdlog::error("{}", ran.message());
  return ran.ExitCode();
}

}  // namespace

// An exception nothing below caught (an allocation failure) ends the supervisor with its message.
int main(int argc, char** argv) {
  try {
    return SupervisorMain(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fleet_supervisor: %s\n", e.what());
    return 1;
  }
}
