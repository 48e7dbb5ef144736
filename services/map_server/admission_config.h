// The map server's "patch_admission" configuration object: how re-mapping jobs judge patches
// (mapping/patch_admission.h), whether a change must be seen by several vehicles
// (mapping/change_corroboration.h) and when a vehicle is quarantined
// (mapping/vehicle_reputation.h). Every key optional, unknown keys rejected, ranges checked with a
// message naming the field.
#pragma once

#include "base/status.h"
#include "io/json_fields.h"
#include "mosaic_upkeep/remap_job.h"

namespace fleetloc::map_server {

// "" or "<option> <what>" for the first option out of range.
std::string PolicyProblem(const mosaic_upkeep::RemapPolicy& policy);

// Reads `object` (the "patch_admission" member, viewed through `fields`) over `policy`'s values:
// types checked here, ranges by PolicyProblem.
Status ReadRemapPolicy(const io::JsonFields& fields, const nlohmann::json& object,
                       mosaic_upkeep::RemapPolicy* policy);

}  // namespace fleetloc::map_server
