// The demo mosaic fleetctl's DDS benchmarks serve (the floors are found by floor_images.h).
#pragma once

#include <filesystem>
#include <string>

#include "base/status.h"

namespace fleetloc::bench {

// The demo floor `image_name` (in DefaultFloorsDir()) imported at 0.5 mm/px as
// `work_dir`/`db_name`, reused if it exists. Returns the mosaic's path.
Result<std::string> EnsureDemoMosaic(const std::string& work_dir, const std::string& image_name,
                                     const std::string& db_name);

}  // namespace fleetloc::bench
