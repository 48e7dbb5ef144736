// run.json (docs/formats.md): vehicle id, camera file and initial pose of a run.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::run_io {

struct RunJson {
  std::string vehicle_id;
  std::filesystem::path camera = "camera.json";  // as written: relative to the run directory
  geometry::Pose2 initial_pose;                  // base_link in map at the first frame's time
  Eigen::Vector3d initial_sigma{0, 0, 0};        // 1-sigma x, y, theta
};

// Reads and validates run.json ("format" "fleetloc-run/1", non-empty vehicle_id and camera,
// finite initial pose, 3 non-negative sigmas; theta wrapped). Unknown members are ignored.
// NotFound when missing, InvalidInput "<file>: field '<name>': ..." otherwise.
Result<RunJson> ReadRunJson(const std::filesystem::path& path);

// Writes run.json atomically; InvalidInput (nothing written) for content ReadRunJson would reject.
Status WriteRunJson(const std::filesystem::path& path, const RunJson& run);

}  // namespace fleetloc::run_io
