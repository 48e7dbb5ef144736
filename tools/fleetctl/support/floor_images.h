// The real floor photographs the benchmarks and `compose-floor` use: where the demo floors are,
// which files of a directory are images, and loading them as 8-bit gray.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::fleetctl {

// deploy/demo/floors of the source tree, relative to the source root.
inline constexpr const char* kFloorsSubdir = "deploy/demo/floors";

// deploy/demo/floors of the source tree: beside the executable's build directory
// (<source>/<build>/bin/fleetctl) or else the source directory this binary was compiled from.
std::filesystem::path DefaultFloorsDir();

// Every image file of `dir` (by extension), sorted by name. NotFound when `dir` does not exist,
// InvalidInput when it holds no image; both name `option` (the flag that chose the directory).
Result<std::vector<std::filesystem::path>> ListFloorImages(const std::filesystem::path& dir,
                                                           const std::string& option);

// The images as 8-bit gray (run_io::ReadGrayImage), in order. The first failure's status otherwise.
Result<std::vector<cv::Mat>> LoadGrayImages(const std::vector<std::string>& paths);

}  // namespace fleetloc::fleetctl
