// `fleetctl bench tracker-stress` (issue 15): the tracker and its peers on floors the project was
// not tuned on (data/stress_floors/floors.json), at three frame sizes, under five camera
// conditions (one held out of tuning), with the holdout floors reported apart from the tuning ones.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/tracker/bench_tracker.h"

namespace fleetloc::bench {

// One manifest entry.
struct StressFloor {
  std::filesystem::path image;
  std::string file, floor_class, split;  // split: one of StressSplits()' names
};

// A manifest split: its name and what its floors were used for.
struct StressSplit {
  const char* name;
  const char* role;
};

// "tuning" (used while tuning), "holdout" (never used while tuning) and "fresh" (photographs of
// another source, added on 2026-12-08 and first run as they came), in the order reports list them.
const std::vector<StressSplit>& StressSplits();

// Whether `split` names a manifest split ("all", which selects them all, is not one).
bool IsStressSplit(const std::string& split);

// A frame size of the suite, "WIDTHxHEIGHT".
struct FrameSize {
  int width = 0, height = 0;
  std::string label;
};

// "WIDTHxHEIGHT" with both within 64..4096; InvalidInput naming --sizes otherwise.
Result<FrameSize> ParseFrameSize(const std::string& text);

// data/stress_floors/floors.json: NotFound / InvalidInput naming the file and the bad entry.
Result<std::vector<StressFloor>> ReadStressManifest(const std::filesystem::path& manifest);

// data/stress_floors/floors.json of the source tree (beside the build, else the compiled-in one).
std::filesystem::path DefaultStressManifest();

// The default conditions: "clean", "fast", "dusty", "all", "marks", "camera". "aisles" is asked for
// by name.
const std::vector<std::string>& StressConditionNames();

// The run settings of a condition for frames of width × height (speed scales with the frame):
//  clean: successive frames overlap by 2/3, mild sensor noise only;
//  fast:  successive frames do not overlap (1.25 frame widths apart), short exposure: more read
//         and shot noise, gain jitter ±25 %, a little motion blur;
//  dusty: dust and grime over 30 % of the floor, strong vignetting (50 % at the corners), gain
//         jitter ±25 %, bias ±20 DN, uneven light (±40 %), lens blur σ 1.5 px;
//  all:   fast and dusty at once;
//  marks: held out of tuning — other occluders: tyre marks over 12 % of the floor, hard-edged
//         debris over 5 %, the vehicle's shadow over 30 % of the frame (60 % darker), vignetting
//         30 %, uneven light ±20 %, gain jitter ±20 %;
//  camera: held out of tuning — another camera: frames 0.6 widths apart with ~4 px of motion
//         blur, JPEG quality 70, defocus σ 1 px, vignetting 35 %, a harder response curve
//         (γ 0.6, S-curve 0.6), read noise 2.5 DN, gain ±15 %, bias ±10 DN.
// InvalidInput for an unknown name.
Status ApplyStressCondition(const std::string& name, BenchSettings* settings);

// The floor image scaled up (bicubic) by the smallest integer factor that makes it at least 1.6×
// the frame in both directions, written once into `dir`; the image itself when it already is.
Result<std::filesystem::path> FloorForFrame(const StressFloor& floor, int width_px, int height_px,
                                            const std::filesystem::path& dir);

}  // namespace fleetloc::bench
