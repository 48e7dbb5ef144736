// `fleetctl bench reloc --stress` (issue 17): global relocalization on the tracker stress suite's
// floors (data/stress_floors, issue 15) — every floor × frame size × camera condition a cell of
// relocalization trials on the floor imported alone (scaled to 1.6 frames as the tracker suite
// does), optionally on a "repeated" copy of it (the floor twice side by side: a self-similar
// floor where a frame inside one copy has two true answers, so the right answer is "ambiguous").
// Tuning and holdout floors are reported in separate tables, each summarised per class × condition.
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "harness/reloc/bench_reloc.h"
#include "relocalization/place_index.h"

namespace fleetloc::bench {

struct RelocStressArgs {
  std::string manifest;  // default: data/stress_floors/floors.json
  std::string split = "all";
  std::vector<std::string> classes;  // empty: all
  std::vector<std::string> sizes{"320x240", "640x480", "1280x1024"};
  std::vector<std::string> conditions{"clean", "fast", "dusty"};
  std::vector<std::string> layouts{"single"};  // "single" and/or "repeated"
  std::string work_dir;
  std::string json;
  relocalization::PlaceIndexOptions index;
  RelocTrialSettings trials;  // frame size, render options and step are set per cell
};

// Runs every selected cell, prints one line per cell and a class × condition summary per split,
// writes every number as JSON when args.json is set. InvalidInput for a bad manifest, size or
// condition; a cell's error otherwise.
Status RunRelocStress(const RelocStressArgs& args);

}  // namespace fleetloc::bench
