// The map server's "patch_intake" and "retention" configuration objects: what a vehicle may put in
// the patch store (rate, quotas, the decoding queue) and how long old tile versions and patches are
// kept (mosaic/mosaic_retention.h). Every key optional, unknown keys rejected, ranges checked.
#pragma once

#include <string>

#include "base/status.h"
#include "io/json_fields.h"
#include "map_server/patch_service.h"
#include "mosaic/mosaic_retention.h"

namespace fleetloc::map_server {

struct Retention {
  mosaic::RetentionPolicy policy;
  double prune_period_s =
      3600;  // the server prunes this often (0: never; fleetctl mosaic prune by hand)
};

// "" or "<option> <what>" for the first value out of range.
std::string IntakeProblem(const PatchIntake& intake);
std::string RetentionProblem(const Retention& retention);

// Read `object` (viewed through `fields`) over the values given; ranges: the *Problem functions.
Status ReadPatchIntake(const io::JsonFields& fields, const nlohmann::json& object,
                       PatchIntake* intake);
Status ReadRetention(const io::JsonFields& fields, const nlohmann::json& object,
                     Retention* retention);

}  // namespace fleetloc::map_server
