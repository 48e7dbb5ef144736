// Writing a simulated run to disk (docs/formats.md): every frame rendered and written as a PNG,
// then the run's tables with the io library. Shared by `fleetctl sim` and `fleetctl bench tracker`
// so a benchmark run is exactly what `fleetctl sim` would have written.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "base/status.h"
#include "run_io/run.h"
#include "sim/run_simulator.h"

namespace fleetloc::fleetctl {

// The default camera of simulated runs: width × height pixels at the floor's resolution, principal
// point at the image centre, mounted 0.40 m ahead of base_link.
run_io::CameraFile DefaultSimCamera(int width_px, int height_px, double resolution_m);

// Makes `dir` ready for a new run: created if missing; an existing non-empty directory only when
// `overwrite` (InvalidInput otherwise), and then only the run's own files are removed.
// Internal if the directory cannot be created.
Status PrepareRunDir(const std::filesystem::path& dir, bool overwrite);

// Wall-clock milliseconds spent rendering frames and waiting for their files to be written.
struct FrameTimes {
  double render_ms = 0.0;
  double write_wait_ms = 0.0;
};

// Called after each frame is rendered with the frames done so far and the total.
using FrameProgress = std::function<void(int done, int total)>;

// Renders every frame of `simulator` into `dir`/frames/NNNNNN.png and writes run.json,
// camera.json, frames.csv, odometry.csv and truth.csv; returns the run as written (frame paths
// absolute). `dir` must have been prepared with PrepareRunDir. Adds the time spent to *times
// when given. Internal when a file cannot be written; InvalidInput if the io library refuses
// the run's content.
Result<run_io::Run> WriteSimulatedRun(sim::RunSimulator& simulator,
                                      const run_io::CameraFile& camera,
                                      const std::filesystem::path& dir,
                                      const std::string& vehicle_id,
                                      const FrameProgress& progress = {},
                                      FrameTimes* times = nullptr);

}  // namespace fleetloc::fleetctl
