// `fleetctl bench reloc` trials: a vehicle put down at a random pose (uniform over the mosaic area
// where a full frame fits, uniform heading) sees sim-rendered frames (5 Hz, driving straight at
// 0.3 m per frame, backwards when a step ahead leaves the floor, to and fro along its heading
// where the floor is too short); each frame is relocalized with no prior, from a cold tile cache,
// until a pose is returned. Time to the first correct pose counts the relocalizer's time of every
// attempt plus the frame period for each frame it waited for.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "base/status.h"
#include "mosaic/tile_store.h"
#include "relocalization/place_index.h"
#include "relocalization/relocalizer.h"
#include "sim/sim_options.h"

namespace fleetloc::bench {

struct RelocTrialSettings {
  int trials = 200;
  int attempts = 3;             // frames tried per trial
  double frame_period_s = 0.2;  // 5 Hz
  double step_m = 0.3;          // distance driven between frames
  double max_error_m = 0.002;   // a returned pose is correct within both
  double max_error_rad = 0.5 * M_PI / 180;
  double target_s = 1.0;  // "within 1 s"
  std::uint64_t seed = 1;
  long long tile_cache_bytes = 64LL << 20;  // per trial (cold)
  int width_px = 640, height_px = 480;      // the camera's frames
  sim::RenderOptions render;                // camera effects (default: `fleetctl sim`'s)
  // OpenCV threads while a frame is relocalized, and the dense searches' stripes
  // (DensePlaceSearchOptions::threads); 1 otherwise, so the index builds fork with no worker
  // busy and the rendering stays on one core. 2 by default, as the tracker agent's
  // relocalize_threads: a lost vehicle's tracker is idle (1 measures one core).
  int threads = 2;
  relocalization::RelocalizerOptions relocalizer;
};

struct RelocTrial {
  bool found = false;    // some attempt returned a pose
  bool correct = false;  // that pose within the error bounds
  int attempts = 0;      // frames used
  double error_m = 0, error_rad = 0;
  double time_to_pose_s = 0;  // relocalizer time of all attempts + waiting for later frames
  std::vector<relocalization::Relocalization> runs;  // one per attempt
  int accepted_run = -1;                             // the run that returned the pose
  // With multi-frame relocalization (relocalizer.trajectory_frames > 1; odometry 2 % long and
  // 0.5° per metre off): the single-frame outcome of the same frames — the first attempt whose
  // own frame was accepted — for side-by-side tables.
  bool single_found = false, single_correct = false;
  double single_time_s = 0;
  // Poses the features found and the twin check (or the self-similarity report) refused: whether
  // each was right after all, so the twin rule's margin can be judged (issue 17).
  struct Refused {
    bool correct = false;
    double error_m = 0, error_rad = 0;
    double own = 0, twin = 0;  // the pose's dense correlation and its best distinct alternative's
    int twin_inliers = 0;
    bool by_report = false;  // refused by the self-similarity report, not the twin check
  };
  std::vector<Refused> refused;
  // Not found, refused as ambiguous at least once, and the floor itself repeats where every frame
  // of the trial looked (see FloorRepeatsAt in bench_reloc.cpp): no frame of those places can
  // tell them from their twins, and "not found" is the right answer.
  bool at_repeated_place = false;
  relocalization::Relocalizer::DenseMemory memory;  // the trial's relocalizer's dense searches
};

// Runs the trials on the mosaic of `store` with `index` (null: none, the dense search alone);
// logs progress. Internal if the
// relocalizer rejects a rendered frame (a bug).
Result<std::vector<RelocTrial>> RunRelocTrials(const std::shared_ptr<mosaic::TileStore>& store,
                                               const relocalization::PlaceIndex* index,
                                               const RelocTrialSettings& settings);

// The trials' counts (correct, within target_s, wrong, not found, of those not found the ones at
// a place the floor repeats), time percentiles, every failed trial and every trial found after
// target_s with what the relocalizer saw, the gate margins of every accepted pose, and the
// contrasts of every pose accepted after its rivals were told apart.
nlohmann::json RelocTrialStats(const std::vector<RelocTrial>& trials, const RelocTrialSettings& s);

}  // namespace fleetloc::bench
