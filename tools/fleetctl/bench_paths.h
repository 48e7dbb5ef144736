// Where fleetctl's benchmarks find the demo floors of the source tree.
#pragma once

#include <filesystem>
#include <string>

#include "base/status.h"

namespace fleetloc::fleetctl {

// deploy/demo/floors of the source tree: beside the executable's build directory
// (<source>/<build>/bin/fleetctl) or else the source directory this binary was compiled from.
std::filesystem::path DefaultFloorsDir();

// The demo floor `image_name` (in DefaultFloorsDir()) imported at 0.5 mm/px as
// `work_dir`/`db_name`, reused if it exists. Returns the mosaic's path.
Result<std::string> EnsureDemoMosaic(const std::string& work_dir, const std::string& image_name,
                                     const std::string& db_name);

}  // namespace fleetloc::fleetctl
