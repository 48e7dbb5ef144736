// A relocalization result as JSON, for `fleetctl reloc` and `fleetctl bench reloc` (the index
// they relocalize with comes from mosaic/place_index_cache.h).
#pragma once

#include <nlohmann/json.hpp>

#include "relocalization/relocalizer.h"

namespace fleetloc::fleetctl {

// found, pose, covariance (upper triangle as in poses.csv), reason, counts and stage times.
nlohmann::json RelocalizationJson(const relocalization::Relocalization& result);

}  // namespace fleetloc::fleetctl
