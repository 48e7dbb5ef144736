// tracker_agent: one vehicle's localization over the shared mosaic, until its input ends or
// SIGINT/SIGTERM.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "cli/command_line.h"
#include "run_io/tracker_config.h"
#include "runtime/logging.h"
#include "runtime/stop_signal.h"
#include "tracker_agent/live_input.h"
#include "tracker_agent/position_update_setup.h"
#include "tracker_agent/replay_input.h"
#include "tracker_agent/sim_input.h"
#include "tracker_agent/tracker_agent.h"

namespace {

using namespace fleetloc;

// The pose the agent starts from: the given one, or none when it is to relocalize globally.
std::optional<geometry::PoseWithCovariance> StartPose(const tracker_agent::AgentConfig& config,
                                                      const geometry::PoseWithCovariance& given) {
  if (config.start_pose == "relocalize") return std::nullopt;
  return given;
}

// A live simulated vehicle driving forever over the configured floor image.
Status RunSimulatedVehicle(const tracker_agent::AgentConfig& config,
                           const tracking::TrackerOptions& options, const std::atomic<bool>& stop) {
  Result<cv::Mat> floor = run_io::ReadGrayImage(config.sim_floor);
  if (!floor.ok()) return floor.status();
  const double res = config.sim_resolution_m;
  mosaic::ImageRasterSource source(*floor, {0.0, floor->rows * res, res});
  sim::SimOptions sim;
  sim.timing.frames = 600;  // one stretch; the next continues from its end
  sim.timing.frame_rate_hz = config.sim_rate_hz;
  sim.route.speed_px_s = config.sim_speed_px_s;
  sim.route.start_fraction = config.sim_start_fraction;
  sim.seed = static_cast<std::uint64_t>(config.sim_seed);
  run_io::CameraFile camera;
  camera.model = sim::DefaultSimCameraModel(640, 480, res);
  auto input = tracker_agent::SimInput::Create(&source, camera.model, sim, config.paced);
  if (!input.ok()) return input.status();
  auto agent = tracker_agent::TrackerAgent::Create(
      config, camera, StartPose(config, (*input)->initial_pose()), options);
  if (!agent.ok()) return agent.status();
  return (*agent)->Run(**input, stop);
}

// A real vehicle: a live camera and ROS 2 odometry; the start pose from the vehicle's stack
// (initialpose) or, with start_pose "relocalize", from the place index.
Status RunLiveVehicle(const tracker_agent::AgentConfig& config,
                      const tracking::TrackerOptions& options, const std::atomic<bool>& stop) {
  Result<run_io::CameraFile> camera = run_io::ReadCameraJson(config.live.camera_path);
  if (!camera.ok()) return camera.status();
  auto agent = tracker_agent::TrackerAgent::Create(config, *camera, std::nullopt, options);
  if (!agent.ok()) return agent.status();
  auto input = tracker_agent::LiveInput::Create(config, *camera,
                                                tracker_agent::LiveInput::OpenerFor(config));
  if (!input.ok()) return input.status();
  return (*agent)->Run(**input, stop);
}

Status RunAgent(const tracker_agent::AgentConfig& config, const std::atomic<bool>& stop) {
  FLEETLOC_RETURN_IF_ERROR(tracker_agent::Validate(config));
  tracking::TrackerOptions options;
  if (!config.tracker_options_path.empty()) {
    Result<tracking::TrackerOptions> read = run_io::ReadTrackerOptions(config.tracker_options_path);
    if (!read.ok()) return read.status();
    options = *read;
  }
  if (config.source == "sim") return RunSimulatedVehicle(config, options, stop);
  if (tracker_agent::IsLiveSource(config.source)) return RunLiveVehicle(config, options, stop);
  Result<run_io::Run> run = run_io::ReadRun(config.run_path);
  if (!run.ok()) return run.status();
  const Eigen::Vector3d sigma = run->initial_sigma;
  const geometry::PoseWithCovariance initial{run->initial_pose,
                                             sigma.cwiseProduct(sigma).asDiagonal()};
  auto position_update = tracker_agent::PositionUpdateForRun(config, *run);
  if (!position_update.ok()) return position_update.status();
  auto agent = tracker_agent::TrackerAgent::Create(config, run->camera, StartPose(config, initial),
                                                   options, std::move(position_update).value());
  if (!agent.ok()) return agent.status();
  tracker_agent::ReplayInput input(std::move(run).value(), config.paced);
  return (*agent)->Run(input, stop);
}

// The command line's overrides of the configuration; an empty string or a negative number is
// "not given".
struct CommandLineOptions {
  std::string config_path, vehicle_id, run, landmarks, sim_floor, dds_config, outbox, summary;
  std::string metrics_port_file;
  int domain = -1;
  int metrics_port = -1;
  bool fast = false;
  bool relocalize = false;
};

// Declares the agent's flags on `app`, writing into `options`.
void AddOptions(CLI::App& app, CommandLineOptions& options) {
  app.add_option("--config", options.config_path, "Configuration (JSON; defaults for absent keys)");
  app.add_option("--vehicle-id", options.vehicle_id, "Vehicle id (overrides the configuration)");
  app.add_option("--run", options.run, "Replay this run directory (overrides the configuration)");
  app.add_option("--landmarks", options.landmarks,
                 "Landmark map for the position updates (default: the run's landmarks.csv)");
  app.add_option("--sim-floor", options.sim_floor,
                 "Drive a live simulated vehicle over this floor image forever");
  app.add_option("--domain", options.domain, "DDS domain id (overrides the configuration)");
  app.add_option("--dds-config", options.dds_config,
                 "Cyclone DDS XML (default: built-in loopback)");
  app.add_option("--metrics-port", options.metrics_port,
                 "Serve Prometheus /metrics on this port (0: any free one; off by default)");
  app.add_option("--metrics-port-file", options.metrics_port_file,
                 "Write the bound metrics port into this file");
  app.add_option("--outbox", options.outbox, "Patch outbox file (overrides the configuration)");
  app.add_option("--summary", options.summary,
                 "Write a JSON summary (frames, cycle times) at exit");
  app.add_flag("--fast", options.fast, "Replay as fast as possible instead of at recorded speed");
  app.add_flag("--relocalize", options.relocalize,
               "Start without the given initial pose: find it with the map server's place index");
}

// Applies the flags that were given over the configuration file's values (or the defaults).
void ApplyOverrides(const CommandLineOptions& options, tracker_agent::AgentConfig& config) {
  if (!options.vehicle_id.empty()) config.vehicle_id = options.vehicle_id;
  if (!options.run.empty()) {
    config.run_path = options.run;
    config.source = "replay";
  }
  if (!options.sim_floor.empty()) {
    config.sim_floor = options.sim_floor;
    config.source = "sim";
  }
  if (options.domain >= 0) config.domain_id = options.domain;
  if (!options.dds_config.empty()) config.dds_config_path = options.dds_config;
  if (options.fast) config.paced = false;
  if (options.relocalize) config.start_pose = "relocalize";
  if (!options.outbox.empty()) config.outbox_path = options.outbox;
  if (!options.summary.empty()) config.summary_path = options.summary;
  if (!options.landmarks.empty()) config.landmarks_path = options.landmarks;
  if (options.metrics_port >= 0) {
    config.metrics.enabled = true;
    config.metrics.port = options.metrics_port;
  }
  if (!options.metrics_port_file.empty()) config.metrics.port_file = options.metrics_port_file;
}

int AgentMain(int argc, char** argv) {
  CLI::App app{"fleetloc tracker agent: one vehicle's pose over the shared mosaic, live over DDS"};
  CommandLineOptions options;
  AddOptions(app, options);
  if (auto exit_status = fleetloc::cli::ParseCommandLine(app, "tracker_agent", argc, argv))
    return *exit_status;
  tracker_agent::AgentConfig config;
  if (!options.config_path.empty()) {
    auto loaded = tracker_agent::LoadAgentConfig(options.config_path);
    if (!loaded.ok()) {
      std::fprintf(stderr, "tracker_agent: %s\n", loaded.status().message().c_str());
      return loaded.status().ExitCode();
    }
    config = *loaded;
  }
  ApplyOverrides(options, config);
  runtime::SetupLogging(config.vehicle_id);
  const Status ran = RunAgent(config, runtime::InstallStopSignals());
  if (!ran.ok()) spdlog::error("{}", ran.message());
  return ran.ExitCode();
}

}  // namespace

// An exception nothing below caught (an allocation failure) ends the agent with its message.
int main(int argc, char** argv) {
  try {
    return AgentMain(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tracker_agent: %s\n", e.what());
    return 1;
  }
}
