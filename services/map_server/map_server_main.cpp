// map_server: serves the shared floor mosaic over DDS until SIGINT/SIGTERM.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "cli/command_line.h"
#include "map_server/map_server.h"
#include "runtime/logging.h"
#include "runtime/stop_signal.h"

namespace {

int MapServerMain(int argc, char** argv) {
  using fleetloc::map_server::MapServerConfig;
  CLI::App app{"fleetloc map server: the shared mosaic over DDS"};
  std::string config_path, mosaic, server_id, dds_config, metrics_port_file;
  int domain = -1, metrics_port = -1;
  app.add_option("--config", config_path, "Configuration (JSON; defaults for absent keys)");
  app.add_option("--mosaic", mosaic, "Mosaic file (overrides the configuration)");
  app.add_option("--server-id", server_id, "Server id (overrides the configuration)");
  app.add_option("--domain", domain, "DDS domain id (overrides the configuration)");
  app.add_option("--dds-config", dds_config, "Cyclone DDS XML (default: built-in loopback)");
  app.add_option("--metrics-port", metrics_port,
                 "Prometheus /metrics port (0: any free one; default 9471)");
  app.add_option("--metrics-port-file", metrics_port_file,
                 "Write the bound metrics port into this file");
  if (auto exit_status = fleetloc::cli::ParseCommandLine(app, "map_server", argc, argv))
    return *exit_status;

  MapServerConfig config;
  if (!config_path.empty()) {
    auto loaded = fleetloc::map_server::LoadMapServerConfig(config_path);
    if (!loaded.ok()) {
      std::fprintf(stderr, "map_server: %s\n", loaded.status().message().c_str());
      return 2;
    }
    config = *loaded;
  }
  if (!mosaic.empty()) config.mosaic_path = mosaic;
  if (!server_id.empty()) config.server_id = server_id;
  if (domain >= 0) config.domain_id = domain;
  if (!dds_config.empty()) config.dds_config_path = dds_config;
  if (metrics_port >= 0) config.metrics.port = metrics_port;
  if (!metrics_port_file.empty()) config.metrics.port_file = metrics_port_file;
  fleetloc::runtime::SetupLogging(config.server_id);
  const std::atomic<bool>& stop = fleetloc::runtime::InstallStopSignals();
  auto server = fleetloc::map_server::MapServer::Create(config);
  if (!server.ok()) {
    spdlog::error("{}", server.status().message());
    return server.status().ExitCode();
  }
  const fleetloc::Status ran = (*server)->Run(stop);
  if (!ran.ok()) spdlog::error("{}", ran.message());
  return ran.ExitCode();
}

}  // namespace

// An exception nothing below caught (an allocation failure) ends the server with its message.
int main(int argc, char** argv) {
  try {
    return MapServerMain(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "map_server: %s\n", e.what());
    return 1;
  }
}
