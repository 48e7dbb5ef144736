// `fleetctl bench dense-probe`: the dense place search at the truth of a run's frames (issue 17).
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "relocalization/dense_place_search.h"

namespace fleetloc::bench {

struct DenseProbeArgs {
  std::string mosaic, run;  // the mosaic and a run with truth over it
  int every = 6;            // every k-th frame
  relocalization::DensePlaceSearchOptions dense;
};

// Prints one line per probed frame and the count at the truth. The run's or the mosaic's error
// when either cannot be read; InvalidInput when the run lacks a truth row per frame.
Status RunDenseProbe(const DenseProbeArgs& args);

}  // namespace fleetloc::bench
