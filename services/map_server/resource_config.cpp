// "patch_intake" and "retention" from JSON.
#include "map_server/resource_config.h"

#include <map>

namespace fleetloc::map_server {
namespace {

// Reads each known number of `object` into its target after `scale`; unknown keys are errors.
Status ReadNumbers(const io::JsonFields& fields, const nlohmann::json& object,
                   const std::map<std::string, std::pair<double*, double>>& doubles,
                   const std::map<std::string, std::pair<long long*, long long>>& integers) {
  for (const auto& [key, value] : object.items()) {
    double v = 0;
    if (const auto d = doubles.find(key); d != doubles.end()) {
      FLEETLOC_RETURN_IF_ERROR(fields.NonNegativeNumber(key, &v));
      *d->second.first = v * d->second.second;
    } else if (const auto i = integers.find(key); i != integers.end()) {
      FLEETLOC_RETURN_IF_ERROR(fields.NonNegativeNumber(key, &v));
      if (v != static_cast<double>(static_cast<long long>(v)))
        return fields.Error(key, "must be an integer");
      *i->second.first = static_cast<long long>(v) * i->second.second;
    } else {
      return fields.Error(key, "unknown option");
    }
  }
  return Status::Ok();
}

}  // namespace

std::string IntakeProblem(const PatchIntake& in) {
  const PatchBudgetOptions& b = in.budget;
  if (!(b.patches_per_s > 0)) return "patches_per_s must be > 0";
  if (b.burst < 1) return "burst must be >= 1";
  if (b.max_patches_per_vehicle < 1) return "max_patches_per_vehicle must be >= 1";
  if (b.max_bytes_per_vehicle < (1 << 20)) return "max_mb_per_vehicle must be >= 1";
  if (b.max_bytes_total < b.max_bytes_per_vehicle)
    return "max_store_mb must be >= max_mb_per_vehicle";
  if (in.queue < 1 || in.queue > 4096) return "queue must be in [1, 4096]";
  if (in.max_queued_mb < 1) return "max_queued_mb must be >= 1";
  return "";
}

std::string RetentionProblem(const Retention& r) {
  if (std::string problem = mosaic::RetentionProblem(r.policy); !problem.empty()) return problem;
  if (!(r.prune_period_s == 0 || r.prune_period_s >= 10))
    return "prune_period_s must be 0 (never) or >= 10";
  return "";
}

Status ReadPatchIntake(const io::JsonFields& fields, const nlohmann::json& object,
                       PatchIntake* in) {
  long long burst = in->budget.burst, queue = in->queue, queued_mb = in->max_queued_mb;
  FLEETLOC_RETURN_IF_ERROR(
      ReadNumbers(fields, object, {{"patches_per_s", {&in->budget.patches_per_s, 1.0}}},
                  {{"burst", {&burst, 1}},
                   {"max_patches_per_vehicle", {&in->budget.max_patches_per_vehicle, 1}},
                   {"max_mb_per_vehicle", {&in->budget.max_bytes_per_vehicle, 1LL << 20}},
                   {"max_store_mb", {&in->budget.max_bytes_total, 1LL << 20}},
                   {"queue", {&queue, 1}},
                   {"max_queued_mb", {&queued_mb, 1}}}));
  in->budget.burst = static_cast<int>(std::min(burst, 1LL << 30));
  in->queue = static_cast<int>(std::min(queue, 1LL << 30));
  in->max_queued_mb = static_cast<int>(std::min(queued_mb, 1LL << 30));
  return Status::Ok();
}

Status ReadRetention(const io::JsonFields& fields, const nlohmann::json& object, Retention* r) {
  long long kept = r->policy.tile_versions_kept;
  FLEETLOC_RETURN_IF_ERROR(ReadNumbers(
      fields, object,
      {{"patch_retention_days", {&r->policy.patch_retention_s, 86400.0}},
       {"unfolded_patch_retention_days", {&r->policy.unfolded_patch_retention_s, 86400.0}},
       {"prune_period_s", {&r->prune_period_s, 1.0}}},
      {{"tile_versions_kept", {&kept, 1}}}));
  r->policy.tile_versions_kept = static_cast<int>(std::min(kept, 1LL << 30));
  return Status::Ok();
}

}  // namespace fleetloc::map_server
