// Tracker options <-> JSON through one table of fields, so reading and writing cannot drift apart.
#include "run_io/tracker_config.h"

#include <cmath>
#include <functional>
#include <variant>

#include "io/json_fields.h"

namespace fleetloc::run_io {
namespace {

using Field = std::variant<int*, double*, bool*>;
using FieldTable = std::vector<std::pair<const char*, Field>>;

FieldTable TrackerFields(tracking::TrackerOptions& o) {
  return {{"template_size_px", &o.template_size_px},
          {"weak_template_size_px", &o.weak_template_size_px},
          {"max_templates", &o.max_templates},
          {"min_inliers", &o.min_inliers},
          {"candidate_step_px", &o.candidate_step_px},
          {"texture_window_px", &o.texture_window_px},
          {"min_texture", &o.min_texture},
          {"relative_texture", &o.relative_texture},
          {"texture_quantile", &o.texture_quantile},
          {"spread_sigma_px", &o.spread_sigma_px},
          {"texture_cap_quantile", &o.texture_cap_quantile},
          {"normalize_window_px", &o.normalize_window_px},
          {"match_smoothing_sigma_px", &o.match_smoothing_sigma_px},
          {"min_peak_correlation", &o.min_peak_correlation},
          {"max_ambiguity_ratio", &o.max_ambiguity_ratio},
          {"min_peak_curvature", &o.min_peak_curvature},
          {"search_sigma_multiple", &o.search_sigma_multiple},
          {"min_search_radius_px", &o.min_search_radius_px},
          {"max_search_radius_px", &o.max_search_radius_px},
          {"refine_search_radius_px", &o.refine_search_radius_px},
          {"refine_pass_radius_px", &o.refine_pass_radius_px},
          {"refine_passes", &o.refine_passes},
          {"coarse_above_radius_px", &o.coarse_above_radius_px},
          {"coarse_levels", &o.coarse_levels},
          {"coarse_search_radius_px", &o.coarse_search_radius_px},
          {"coarse_templates", &o.coarse_templates},
          {"coarse_template_size_px", &o.coarse_template_size_px},
          {"measurement_sigma_px", &o.measurement_sigma_px},
          {"outlier_ratio", &o.outlier_ratio},
          {"min_outlier_residual_px", &o.min_outlier_residual_px},
          {"max_coasting_frames", &o.max_coasting_frames},
          {"normalized_cache_mb", &o.normalized_cache_mb},
          {"direct_refine", &o.direct_refine},
          {"polish_max_frame_pixels", &o.polish_max_frame_pixels},
          {"polished_max_templates", &o.polished_max_templates},
          {"polish_dense_max_frame_pixels", &o.polish_dense_max_frame_pixels},
          {"polish_min_frame_pixels", &o.polish_min_frame_pixels},
          {"polish_dense_below_correlation", &o.polish_dense_below_correlation},
          {"polish_dense_max_level_pixels", &o.polish_dense_max_level_pixels},
          {"retry_templates_frames", &o.retry_templates_frames},
          {"direct_first_after_failures", &o.direct_first_after_failures},
          {"max_disagreement_chi2", &o.max_disagreement_chi2}};
}

FieldTable DirectFields(tracking::DirectAlignOptions& d) {
  return {{"coarsest_side_px", &d.coarsest_side_px},
          {"finest_level_pixels", &d.finest_level_pixels},
          {"min_finest_level", &d.min_finest_level},
          {"max_points", &d.max_points},
          {"polish_iterations", &d.polish_iterations},
          {"confirm_polish_iterations", &d.confirm_polish_iterations},
          {"max_polish_shift_px", &d.max_polish_shift_px},
          {"max_polish_next_step_px", &d.max_polish_next_step_px},
          {"polish_single_pass_px", &d.polish_single_pass_px},
          {"polish_max_level_pixels", &d.polish_max_level_pixels},
          {"polish_max_level", &d.polish_max_level},
          {"min_significant_peak_z", &d.min_significant_peak_z},
          {"min_tentative_peak_z", &d.min_tentative_peak_z},
          {"min_significant_correlation", &d.min_significant_correlation},
          {"min_polished_significant_correlation", &d.min_polished_significant_correlation},
          {"min_polish_correlation", &d.min_polish_correlation},
          {"max_iterations", &d.max_iterations},
          {"converged_px", &d.converged_px},
          {"tukey_c", &d.tukey_c},
          {"fit_contrast", &d.fit_contrast},
          {"noise_model", &d.noise_model},
          {"polish_wide_window_px", &d.polish_wide_window_px},
          {"polish_wide_window_max_sigma_ratio", &d.polish_wide_window_max_sigma_ratio},
          {"polish_unsmoothed_max_sigma_ratio", &d.polish_unsmoothed_max_sigma_ratio},
          {"max_view_blur_px", &d.max_view_blur_px},
          {"view_blur_step_px", &d.view_blur_step_px},
          {"view_blur_every_frames", &d.view_blur_every_frames},
          {"occluder_contrast_ratio", &d.occluder_contrast_ratio},
          {"correlation_factor", &d.correlation_factor},
          {"search_above_px", &d.search_above_px},
          {"max_search_px", &d.max_search_px},
          {"search_level_pixels", &d.search_level_pixels},
          {"search_sigma_multiple", &d.search_sigma_multiple},
          {"peak_exclusion_px", &d.peak_exclusion_px},
          {"max_heading_steps", &d.max_heading_steps},
          {"heading_probe_px", &d.heading_probe_px},
          {"significant_peak_ends_search", &d.significant_peak_ends_search},
          {"verify_rival_peak", &d.verify_rival_peak},
          {"rival_same_place_px", &d.rival_same_place_px},
          {"max_sigma_px", &d.max_sigma_px},
          {"min_correlation", &d.min_correlation},
          {"min_strong_correlation", &d.min_strong_correlation},
          {"max_strong_peak_ratio", &d.max_strong_peak_ratio},
          {"min_weak_correlation", &d.min_weak_correlation},
          {"max_weak_peak_ratio", &d.max_weak_peak_ratio},
          {"max_weak_prior_chi2", &d.max_weak_prior_chi2},
          {"max_prior_chi2", &d.max_prior_chi2},
          {"min_distinct_correlation", &d.min_distinct_correlation},
          {"max_distinct_peak_ratio", &d.max_distinct_peak_ratio},
          {"max_clear_peak_ratio", &d.max_clear_peak_ratio},
          {"full_resolution_below_pixels", &d.full_resolution_below_pixels},
          {"min_fine_strong_correlation", &d.min_fine_strong_correlation},
          {"max_distinct_prior_chi2", &d.max_distinct_prior_chi2}};
}

FieldTable OdometryFields(tracking::OdometryNoiseOptions& n) {
  return {{"along_sigma_per_m", &n.along_sigma_per_m},
          {"lateral_sigma_per_m", &n.lateral_sigma_per_m},
          {"heading_sigma_per_rad", &n.heading_sigma_per_rad},
          {"heading_sigma_per_m", &n.heading_sigma_per_m},
          {"heading_sigma_per_s", &n.heading_sigma_per_s},
          {"floor_sigma_m", &n.floor_sigma_m},
          {"extrapolation_accel_m_s2", &n.extrapolation_accel_m_s2},
          {"extrapolation_angular_accel_rad_s2", &n.extrapolation_angular_accel_rad_s2}};
}

Status ReadFields(const nlohmann::json& object, const FieldTable& table, const std::string& where,
                  const std::string& prefix) {
  if (!object.is_object()) return InvalidInput(where + ": '" + prefix + "' must be an object");
  for (const auto& [key, value] : object.items()) {
    if (prefix.empty() && (key == "odometry" || key == "direct")) continue;
    const auto it = std::find_if(table.begin(), table.end(),
                                 [&key = key](const auto& f) { return key == f.first; });
    std::string field = where;  // "<where>: field '<prefix><key>': " before each problem
    field.append(": field '").append(prefix).append(key).append("': ");
    if (it == table.end()) return InvalidInput(field + "unknown option");
    if (const auto* b = std::get_if<bool*>(&it->second)) {
      if (!value.is_boolean()) return InvalidInput(field + "must be true or false");
      **b = value.get<bool>();
    } else if (const auto* i = std::get_if<int*>(&it->second)) {
      if (!value.is_number_integer()) {
        return InvalidInput(field + "must be an integer");
      }
      **i = value.get<int>();
    } else {
      if (!value.is_number() || !std::isfinite(value.get<double>())) {
        return InvalidInput(field + "must be a finite number");
      }
      *std::get<double*>(it->second) = value.get<double>();
    }
  }
  return Status::Ok();
}

nlohmann::json WriteFields(const FieldTable& table) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, field] : table) {
    std::visit([&j, &key = key](auto* p) { j[key] = *p; }, field);
  }
  return j;
}

}  // namespace

Result<tracking::TrackerOptions> TrackerOptionsFromJson(const nlohmann::json& object,
                                                        const std::string& where) {
  tracking::TrackerOptions options;
  FLEETLOC_RETURN_IF_ERROR(ReadFields(object, TrackerFields(options), where, ""));
  if (object.contains("odometry")) {
    FLEETLOC_RETURN_IF_ERROR(
        ReadFields(object["odometry"], OdometryFields(options.odometry), where, "odometry."));
  }
  if (object.contains("direct")) {
    FLEETLOC_RETURN_IF_ERROR(
        ReadFields(object["direct"], DirectFields(options.direct), where, "direct."));
  }
  const Status valid = tracking::Validate(options);
  if (!valid.ok()) return InvalidInput(where + ": " + valid.message());
  return options;
}

Result<tracking::TrackerOptions> ReadTrackerOptions(const std::filesystem::path& path) {
  Result<nlohmann::json> json = io::ReadJsonObjectFile(path);
  if (!json.ok()) return json.status();
  return TrackerOptionsFromJson(*json, path.string());
}

nlohmann::json TrackerOptionsToJson(const tracking::TrackerOptions& options) {
  tracking::TrackerOptions copy = options;
  nlohmann::json j = WriteFields(TrackerFields(copy));
  j["odometry"] = WriteFields(OdometryFields(copy.odometry));
  j["direct"] = WriteFields(DirectFields(copy.direct));
  return j;
}

}  // namespace fleetloc::run_io
