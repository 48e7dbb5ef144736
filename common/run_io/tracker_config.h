// Tracker options from JSON: every member optional (defaults from TrackerOptions), unknown members
// rejected so a misspelt option is never silently ignored, then range-checked by Validate().
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "base/status.h"
#include "tracking/tracker_options.h"

namespace fleetloc::run_io {

// `where` names the source in messages (a file path). The odometry noise model is the nested
// object "odometry".
Result<tracking::TrackerOptions> TrackerOptionsFromJson(const nlohmann::json& object,
                                                        const std::string& where);
Result<tracking::TrackerOptions> ReadTrackerOptions(const std::filesystem::path& path);
nlohmann::json TrackerOptionsToJson(const tracking::TrackerOptions& options);

}  // namespace fleetloc::run_io
