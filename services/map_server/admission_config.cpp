// "patch_admission" from JSON into a RemapPolicy.
#include "map_server/admission_config.h"

#include <cmath>
#include <map>

namespace fleetloc::map_server {
namespace {

constexpr double kDegree = M_PI / 180.0;

// A number key and where it goes (`scale` converts the file's unit to the option's).
struct NumberKey {
  double* target;
  double scale = 1.0;
};
struct IntKey {
  int* target;
};

}  // namespace

std::string PolicyProblem(const mosaic_upkeep::RemapPolicy& p) {
  if (std::string problem = mapping::OptionsProblem(p.admission); !problem.empty()) {
    return problem;
  }
  if (std::string problem = mapping::OptionsProblem(p.reputation); !problem.empty()) {
    return "quarantine_" + problem;
  }
  if (p.corroboration.min_vehicles < 1 || p.corroboration.min_vehicles > 16) {
    return "min_vehicles_per_change must be in [1, 16]";
  }
  if (p.max_patches_per_tile < 1 || p.max_patches_per_tile > 256) {
    return "max_patches_per_tile must be in [1, 256]";
  }
  return "";
}

Status ReadRemapPolicy(const io::JsonFields& fields, const nlohmann::json& object,
                       mosaic_upkeep::RemapPolicy* p) {
  mapping::AdmissionOptions& a = p->admission;
  const std::map<std::string, NumberKey> numbers = {
      {"min_search_sigma_px", {&a.min_search_sigma_px}},
      {"max_search_sigma_px", {&a.max_search_sigma_px}},
      {"min_search_sigma_deg", {&a.min_search_sigma_rad, kDegree}},
      {"max_search_sigma_deg", {&a.max_search_sigma_rad, kDegree}},
      {"max_rms_residual_px", {&a.max_rms_residual_px}},
      {"max_disagreement_sigmas", {&a.max_disagreement_sigmas}},
      {"min_disagreement_px", {&a.min_disagreement_px}},
      {"min_disagreement_deg", {&a.min_disagreement_rad, kDegree}},
      {"anchor_ncc", {&a.anchor_ncc}},
      {"changed_ncc", {&a.blocks.min_block_ncc}},
      {"min_anchor_fraction", {&a.min_anchor_fraction}},
      {"min_gain", {&a.min_gain}},
      {"max_gain", {&a.max_gain}},
      {"max_abs_bias", {&a.max_abs_bias}},
      {"max_photometric_rms", {&a.max_photometric_rms}},
      {"max_changed_fraction", {&a.max_changed_fraction}},
      {"min_texture_ratio", {&a.min_texture_ratio}},
      {"max_flattened_fraction", {&a.max_flattened_fraction}},
      {"quarantine_max_refused_fraction", {&p->reputation.max_refused_fraction}},
  };
  const std::map<std::string, IntKey> ints = {
      {"min_inliers", {&a.min_inliers}},
      {"block_px", {&a.blocks.block_px}},
      {"min_anchor_blocks", {&a.min_anchor_blocks}},
      {"min_vehicles_per_change", {&p->corroboration.min_vehicles}},
      {"max_patches_per_tile", {&p->max_patches_per_tile}},
      {"quarantine_window", {&p->reputation.window}},
      {"quarantine_min_judged", {&p->reputation.min_judged}},
  };
  for (const auto& [key, value] : object.items()) {
    if (const auto n = numbers.find(key); n != numbers.end()) {
      double v = 0;
      FLEETLOC_RETURN_IF_ERROR(fields.Number(key, &v));
      *n->second.target = v * n->second.scale;
    } else if (const auto i = ints.find(key); i != ints.end()) {
      FLEETLOC_RETURN_IF_ERROR(fields.PositiveInt(key, i->second.target));
    } else {
      return fields.Error(key, "unknown option");
    }
  }
  return Status::Ok();  // ranges: PolicyProblem, through the server config's Validate()
}

}  // namespace fleetloc::map_server
