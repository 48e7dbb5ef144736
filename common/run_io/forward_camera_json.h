// forward_camera.json (docs/forward_camera.md): the calibrated forward camera of a run's
// `forward/` directory — intrinsics, distortion and the mount with height and pitch.
#pragma once

#include <filesystem>

#include "base/status.h"
#include "mapmatch/forward_camera.h"

namespace fleetloc::run_io {

// NotFound "<file>: not found"; InvalidInput "<file>: field '<name>': <what>" for a missing,
// mistyped or out-of-range member ("mount.height", "K", ...). Unknown members are ignored;
// mount.roll is optional (0). mount.yaw is wrapped to (-pi, pi].
Result<mapmatch::ForwardCameraParams> ReadForwardCameraJson(const std::filesystem::path& path);

// Writes atomically; refuses (InvalidInput, nothing written) parameters the reader would reject.
Status WriteForwardCameraJson(const std::filesystem::path& path,
                              const mapmatch::ForwardCameraParams& params);

}  // namespace fleetloc::run_io
