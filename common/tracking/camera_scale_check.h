// Whether a camera's rectified resolution matches the mosaic it tracks over. The tracker matches
// camera templates against the mosaic at the mosaic's scale: a camera at 2x the mosaic's
// resolution loses almost every frame, so a mismatch beyond the tolerance is refused up front.
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::tracking {

// Relative tolerance: |camera / mosaic - 1| above this is refused (docs/cli.md, "camera.json").
inline constexpr double kMaxCameraResolutionMismatch = 0.05;

// Ok when `camera_resolution_m` is within kMaxCameraResolutionMismatch of
// `mosaic_resolution_m` (both metres per pixel, > 0); else InvalidInput naming both values and
// `camera_source` (e.g. the camera.json path).
Status CheckCameraResolution(double camera_resolution_m, double mosaic_resolution_m,
                             const std::string& camera_source);

}  // namespace fleetloc::tracking
