// The rectifier a camera.json asks for: a raw camera's frames are rectified into the tracker's
// top view, a top-view camera's are used as they are. One place for the offline replay
// (common/replay) and the live agent (LocalizationCore), so both rectify frames the same way.
#pragma once

#include <optional>

#include "calibration/rectifier.h"
#include "run_io/run.h"

namespace fleetloc::rectification {

// The rectifier of a raw camera (camera.json's `raw` block) into `camera.model`; none for a
// top-view camera. Needs a `raw` block that io's camera reader accepted.
std::optional<calibration::Rectifier> RectifierFor(const run_io::CameraFile& camera);

}  // namespace fleetloc::rectification
