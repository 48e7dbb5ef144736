// The peer localizers by name, for the benchmark and fleetctl.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geometry/camera_model.h"
#include "mosaic/raster_source.h"
#include "tracking/frame_localizer.h"

namespace fleetloc::peers {

// "orb", "sift", "ecc", "phase", in that order.
const std::vector<std::string>& PeerNames();

// A peer with its default (tuned) options, or nullptr for an unknown name. `mosaic` must
// outlive the peer.
std::unique_ptr<tracking::FrameLocalizer> MakePeer(const std::string& name,
                                                   const geometry::CameraModel& camera,
                                                   mosaic::RasterSource* mosaic);

}  // namespace fleetloc::peers
