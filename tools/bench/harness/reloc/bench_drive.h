// The relocalization bench's vehicle (see bench_reloc.h): where its frames are, trial by trial,
// on a floor that may be only a few frames across.
#pragma once

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "mosaic/raster_source.h"

namespace fleetloc::bench {

// Whether the whole frame of the camera on base_link at `base` stays on the mosaic at any heading.
bool FrameFits(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
               const geometry::Pose2& base);

// base_link's pose at frame `k` of a trial that starts at `start` (where the frame fits) and
// drives `step_m` between frames: straight ahead when one step fits ahead, else backwards (the
// direction is the trial's, not the frame's); where the floor is too short for k steps, to and
// fro along the heading, reversing where the frame would leave the mosaic. It stands at `start`
// only where it cannot move at all.
geometry::Pose2 PoseAtFrame(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
                            const geometry::Pose2& start, int k, double step_m);

}  // namespace fleetloc::bench
