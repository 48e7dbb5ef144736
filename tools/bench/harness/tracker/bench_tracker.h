// `fleetctl bench tracker`, per floor: import the floor image as a tiled mosaic, write a simulated
// run over it exactly as `fleetctl sim` does, read it back and replay it through fleetloc's tracker
// and each peer localizer over one warm-cached view of the mosaic.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/tile_store.h"
#include "replay/replay.h"
#include "run_io/run.h"
#include "sim/run_simulator.h"
#include "tracking/tracker_options.h"

namespace fleetloc::bench {

// "fleetloc" followed by the peers' names (peers::PeerNames()).
std::vector<std::string> BenchMethodNames();

struct BenchSettings {
  std::filesystem::path work_dir;  // mosaics (reused) and runs (rewritten) of each floor
  double resolution_m = 0.0005;    // floor images' metres per pixel
  int frames = 2000;
  double rate_hz = 5.0;
  double speed_px_s = 3000.0;
  std::uint64_t seed = 1;
  std::vector<std::string> methods;     // each one of BenchMethodNames()
  int peer_frames = 0;                  // peers replay only the first peer_frames frames; 0: all
  int width_px = 640, height_px = 480;  // the simulated camera's frames
  sim::RenderOptions render;            // camera effects (default: `fleetctl sim`'s)
  sim::RouteShape route = sim::RouteShape::kFigureEight;
  tracking::TrackerOptions tracker;  // fleetloc's options (`--tracker-config`; default: defaults)
  // fleetloc replays the run this many times, each with a new tracker, and each frame's time is
  // the least of its replays: what the frame costs without the host's other tenants (this VM's
  // timings jump by up to 2× for seconds at a time). The poses must be the same every time.
  int timing_replays = 1;
};

// Folds a further replay of the same run into `first`: each frame's time the least of the two.
// Internal when its poses (status and pose, NaN equal to NaN) or frame count differ from the
// first's.
Status TakeLeastTimes(const replay::ReplayResult& again, replay::ReplayResult* first);

// Reads `path` (tracker options JSON, as `fleetctl track --config`) into settings->tracker; an
// empty path keeps the defaults.
Status LoadBenchTrackerOptions(const std::string& path, BenchSettings* settings);

// Opens floor_dir/mosaic.db made from `image` at `resolution_m`, importing it first unless the one
// there was made from the same file (size, mtime, resolution) and opens. NotFound for a missing
// image; the import's error; Internal when the directory cannot be created.
Result<std::shared_ptr<mosaic::TileStore>> OpenFloorMosaic(const std::filesystem::path& image,
                                                           double resolution_m,
                                                           const std::filesystem::path& floor_dir);

// One method's replay of (the first frames of) a run. `run` holds exactly the frames and truth
// rows that were replayed, so it scores the replay as `fleetctl track` would.
struct MethodReplay {
  std::string label;  // the method's name, or "fleetloc@N" for fleetloc's first N frames
  run_io::Run run;
  replay::ReplayResult replayed;
};

struct FloorBench {
  std::string name;  // the image's file name
  std::filesystem::path image, mosaic, run_dir;
  int width_px = 0, height_px = 0;
  sim::SimSummary sim;
  int frames = 0;                     // of the run (fleetloc replays all)
  int peer_frames = 0;                // frames the peers replayed
  std::vector<MethodReplay> methods;  // in settings order
  std::size_t tile_cache_bytes = 0;   // raw tiles cached at the end
};

// The first `count` frames of a run (and their truth rows); odometry is kept whole.
run_io::Run FirstFrames(const run_io::Run& run, std::size_t count);

// Benchmarks every method on one floor image. NotFound / InvalidInput (exit status 2) for a
// missing or undecodable image or settings the simulator rejects (e.g. a floor too small for the
// camera); Internal on I/O failures.
Result<FloorBench> BenchFloor(const std::filesystem::path& image, const BenchSettings& settings);

}  // namespace fleetloc::bench
