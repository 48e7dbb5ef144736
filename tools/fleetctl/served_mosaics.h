// `fleetctl mosaic info --domain N`: the mosaics the running map servers announce over DDS.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "base/status.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::fleetctl {

// One server's MosaicInfo as JSON (mosaic, version, geometry, the tile range it owns).
nlohmann::json MosaicInfoJson(const fleetloc_MosaicInfo& info);

// Prints {"domain": N, "servers": [...]} with each server's MosaicInfo as JSON, after listening
// for `wait_s` seconds. NotFound when no map server answered.
Status PrintServedMosaics(int domain, double wait_s, const std::string& dds_config);

}  // namespace fleetloc::fleetctl
