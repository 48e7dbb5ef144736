// Where fleetctl's benchmarks find the demo floors of the source tree.
#pragma once

#include <filesystem>

namespace fleetloc::fleetctl {

// deploy/demo/floors of the source tree: beside the executable's build directory
// (<source>/<build>/bin/fleetctl) or else the source directory this binary was compiled from.
std::filesystem::path DefaultFloorsDir();

}  // namespace fleetloc::fleetctl
