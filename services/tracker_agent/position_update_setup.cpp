// Setting up the agent's position update from its run and configuration.
#include "tracker_agent/position_update_setup.h"

#include <spdlog/spdlog.h>

#include "run_io/mapmatch_files.h"

namespace fleetloc::tracker_agent {

namespace fs = std::filesystem;

PositionUpdateOptions PositionUpdateOptionsFrom(const AgentConfig& config) {
  PositionUpdateOptions options;
  options.period_s = config.position_update_period_s;
  options.window_s = config.position_update_window_s;
  options.fit.weight_half_life_s = config.position_update_half_life_s;
  return options;
}

Result<std::unique_ptr<AgentPositionUpdate>> PositionUpdateForRun(const AgentConfig& config,
                                                                  const run_io::Run& run) {
  fs::path landmarks_csv = config.landmarks_path;
  std::error_code ec;
  if (landmarks_csv.empty() && fs::exists(run.dir / "landmarks.csv", ec)) {
    landmarks_csv = run.dir / "landmarks.csv";
  }
  if (!run.forward) {
    if (!landmarks_csv.empty())
      spdlog::info("no forward camera in {}: no position updates", run.dir.string());
    return std::unique_ptr<AgentPositionUpdate>();
  }
  if (landmarks_csv.empty()) {
    spdlog::warn(
        "{} has forward camera images but no landmark map (landmarks.csv): no position updates",
        run.dir.string());
    return std::unique_ptr<AgentPositionUpdate>();
  }
  Result<run_io::LandmarkMap> map = run_io::ReadLandmarksCsv(landmarks_csv);
  if (!map.ok()) return map.status();
  auto update = AgentPositionUpdate::Create(run.forward->camera, map->positions,
                                            PositionUpdateOptionsFrom(config));
  if (!update.ok()) {
    return Status(update.status().code(),
                  landmarks_csv.string() + ": " + update.status().message());
  }
  spdlog::info("position updates every {} s with {} forward images and {} landmarks ({})",
               config.position_update_period_s, run.forward->frames.size(), map->positions.size(),
               landmarks_csv.string());
  return std::move(update).value();
}

}  // namespace fleetloc::tracker_agent
