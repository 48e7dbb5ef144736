// Validation of tracker options.
#include "tracking/tracker_options.h"

#include <cmath>
#include <string>

namespace fleetloc::tracking {
namespace {

Status Check(bool ok, const char* field, const char* rule) {
  return ok ? Status::Ok() : InvalidInput(std::string("tracker option '") + field + "' " + rule);
}

// The pyramid, the Gauss–Newton iterations, the polish and the view blur.
Status ValidateDirectLevels(const DirectAlignOptions& d) {
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.coarsest_side_px >= 16, "direct.coarsest_side_px", "must be ≥ 16"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.finest_level_pixels >= 1000, "direct.finest_level_pixels", "must be ≥ 1000"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.min_finest_level >= 0 && d.min_finest_level <= 3,
                                 "direct.min_finest_level", "must be in [0, 3]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_points >= 100 && d.max_points <= 1000000,
                                 "direct.max_points", "must be in [100, 1000000]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_iterations >= 1 && d.max_iterations <= 100,
                                 "direct.max_iterations", "must be in [1, 100]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.polish_iterations >= 0 && d.polish_iterations <= 10,
                                 "direct.polish_iterations", "must be in [0, 10]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.confirm_polish_iterations >= 0 && d.confirm_polish_iterations <= 10,
            "direct.confirm_polish_iterations", "must be in [0, 10]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.max_polish_shift_px > 0, "direct.max_polish_shift_px", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.min_polish_correlation >= 0 && d.min_polish_correlation < 1,
                                 "direct.min_polish_correlation", "must be in [0, 1)"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.max_polish_next_step_px > 0, "direct.max_polish_next_step_px", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.polish_max_level_pixels >= 0, "direct.polish_max_level_pixels", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.polish_max_level >= 0 && d.polish_max_level <= 4,
                                 "direct.polish_max_level", "must be in [0, 4]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.polish_single_pass_px >= 0 && d.polish_single_pass_px <= d.max_polish_next_step_px,
            "direct.polish_single_pass_px", "must be in [0, direct.max_polish_next_step_px]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.converged_px > 0, "direct.converged_px", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_view_blur_px >= 0 && d.max_view_blur_px <= 5,
                                 "direct.max_view_blur_px", "must be in [0, 5]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.view_blur_step_px >= 0.1 && d.view_blur_step_px <= 2,
                                 "direct.view_blur_step_px", "must be in [0.1, 2]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.view_blur_every_frames >= 1, "direct.view_blur_every_frames", "must be ≥ 1"));
  return Status::Ok();
}

// The robust weights, the coarse search and the validation of a fit.
Status ValidateDirectSearch(const DirectAlignOptions& d) {
  FLEETLOC_RETURN_IF_ERROR(Check(d.tukey_c > 1, "direct.tukey_c", "must be > 1"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.occluder_contrast_ratio > 1, "direct.occluder_contrast_ratio", "must be > 1"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.correlation_factor >= 1, "direct.correlation_factor", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.search_above_px >= 0, "direct.search_above_px", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_search_px >= 1 && d.max_search_px <= 128,
                                 "direct.max_search_px", "must be in [1, 128]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.search_sigma_multiple >= 1 && d.search_sigma_multiple <= 10,
                                 "direct.search_sigma_multiple", "must be in [1, 10]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.search_level_pixels >= 1000, "direct.search_level_pixels", "must be ≥ 1000"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.peak_exclusion_px >= 1, "direct.peak_exclusion_px", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_heading_steps >= 0 && d.max_heading_steps <= 10,
                                 "direct.max_heading_steps", "must be in [0, 10]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.heading_probe_px >= 0 && d.heading_probe_px <= 8,
                                 "direct.heading_probe_px", "must be in [0, 8]"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_sigma_px > 0, "direct.max_sigma_px", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.full_resolution_below_pixels >= 0,
                                 "direct.full_resolution_below_pixels", "must be ≥ 0"));
  for (const auto& [value, name] :
       {std::pair{d.min_correlation, "direct.min_correlation"},
        {d.min_strong_correlation, "direct.min_strong_correlation"},
        {d.min_weak_correlation, "direct.min_weak_correlation"},
        {d.min_distinct_correlation, "direct.min_distinct_correlation"},
        {d.min_fine_strong_correlation, "direct.min_fine_strong_correlation"}}) {
    FLEETLOC_RETURN_IF_ERROR(Check(value > -1 && value < 1, name, "must be in (-1, 1)"));
  }
  for (const auto& [value, name] :
       {std::pair{d.max_strong_peak_ratio, "direct.max_strong_peak_ratio"},
        {d.max_weak_peak_ratio, "direct.max_weak_peak_ratio"},
        {d.max_distinct_peak_ratio, "direct.max_distinct_peak_ratio"},
        {d.max_clear_peak_ratio, "direct.max_clear_peak_ratio"}}) {
    FLEETLOC_RETURN_IF_ERROR(Check(value > 0 && value <= 1, name, "must be in (0, 1]"));
  }
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.min_significant_peak_z > 0, "direct.min_significant_peak_z", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.min_tentative_peak_z >= 0, "direct.min_tentative_peak_z", "must be >= 0 (0: off)"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.polish_wide_window_px >= 0, "direct.polish_wide_window_px",
                                 "must be >= 0 (0: the mosaic's window only)"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.polish_wide_window_max_sigma_ratio > 0,
                                 "direct.polish_wide_window_max_sigma_ratio", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.polish_unsmoothed_max_sigma_ratio >= 0,
                                 "direct.polish_unsmoothed_max_sigma_ratio", "must be >= 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.min_polished_significant_correlation > -1 &&
                d.min_polished_significant_correlation <= d.min_significant_correlation,
            "direct.min_polished_significant_correlation",
            "must be in (-1, min_significant_correlation]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(d.rival_same_place_px >= 0, "direct.rival_same_place_px", "must be >= 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_prior_chi2 > 0 && d.max_weak_prior_chi2 > 0,
                                 "direct.max_prior_chi2", "and max_weak_prior_chi2 must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(d.max_distinct_prior_chi2 >= d.max_prior_chi2,
                                 "direct.max_distinct_prior_chi2", "must be ≥ max_prior_chi2"));
  return Status::Ok();
}

// Template sizes, texture selection and matching.
Status ValidateTemplates(const TrackerOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.template_size_px >= 8 && o.template_size_px <= 128 && o.template_size_px % 4 == 0,
            "template_size_px", "must be a multiple of 4, in [8, 128]"));
  FLEETLOC_RETURN_IF_ERROR(Check(
      o.weak_template_size_px == 0 ||
          (o.weak_template_size_px > o.template_size_px && o.weak_template_size_px <= 128 &&
           o.weak_template_size_px % 8 == 0 && o.weak_template_size_px >> o.coarse_levels >= 8),
      "weak_template_size_px",
      "must be 0 or a multiple of 8 above template_size_px, at most 128, and at least 8 "
      "pixels at the coarsest level"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.coarse_template_size_px >= 8 && o.coarse_template_size_px <= o.template_size_px &&
                o.coarse_template_size_px % 8 == 0,
            "coarse_template_size_px", "must be a multiple of 8, in [8, template_size_px]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.max_templates >= 2 && o.max_templates <= 256, "max_templates",
                                 "must be in [2, 256]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.min_inliers >= 2 && o.min_inliers <= o.max_templates,
                                 "min_inliers", "must be in [2, max_templates]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.candidate_step_px >= 1, "candidate_step_px", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.texture_window_px >= 3 && o.texture_window_px % 2 == 1,
                                 "texture_window_px", "must be odd, ≥ 3"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.normalize_window_px >= 3 && o.normalize_window_px % 2 == 1,
                                 "normalize_window_px", "must be odd, ≥ 3"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.match_smoothing_sigma_px >= 0 && o.match_smoothing_sigma_px <= 4,
                                 "match_smoothing_sigma_px", "must be in [0, 4]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.min_texture >= 0, "min_texture", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.relative_texture >= 0 && o.relative_texture <= 1,
                                 "relative_texture", "must be in [0, 1]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.texture_quantile >= 0 && o.texture_quantile <= 1,
                                 "texture_quantile", "must be in [0, 1]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.spread_sigma_px > 0, "spread_sigma_px", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.texture_cap_quantile >= 0 && o.texture_cap_quantile < 1,
                                 "texture_cap_quantile", "must be in [0, 1)"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.min_peak_correlation > -1 && o.min_peak_correlation < 1,
                                 "min_peak_correlation", "must be in (-1, 1)"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.max_ambiguity_ratio > 0 && o.max_ambiguity_ratio <= 1,
                                 "max_ambiguity_ratio", "must be in (0, 1]"));
  return Status::Ok();
}

// The search radii, the coarse levels, the filter and the fall-backs.
Status ValidateSearchAndFilter(const TrackerOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.search_sigma_multiple > 0, "search_sigma_multiple", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.min_search_radius_px >= 1 && o.min_search_radius_px <= o.max_search_radius_px,
            "min_search_radius_px", "must be in [1, max_search_radius_px]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.refine_search_radius_px >= 1, "refine_search_radius_px", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.refine_passes >= 0 && o.refine_passes <= 5, "refine_passes", "must be in [0, 5]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.refine_pass_radius_px >= 1 && o.refine_pass_radius_px <= o.refine_search_radius_px,
            "refine_pass_radius_px", "must be in [1, refine_search_radius_px]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.coarse_search_radius_px >= 1, "coarse_search_radius_px", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.coarse_above_radius_px >= o.refine_search_radius_px,
                                 "coarse_above_radius_px", "must be ≥ refine_search_radius_px"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.coarse_levels >= 1 && o.coarse_levels <= 3, "coarse_levels", "must be in [1, 3]"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.coarse_template_size_px >> o.coarse_levels >= 8,
                                 "coarse_template_size_px",
                                 "must keep ≥ 8 px at the coarsest level (coarse_levels)"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.coarse_templates >= o.min_inliers, "coarse_templates", "must be ≥ min_inliers"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.measurement_sigma_px > 0, "measurement_sigma_px", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.outlier_ratio > 1, "outlier_ratio", "must be > 1"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.normalized_cache_mb >= 1, "normalized_cache_mb", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(Check(o.max_coasting_frames >= 0, "max_coasting_frames", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.retry_templates_frames >= 0, "retry_templates_frames", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.direct_first_after_failures >= 1, "direct_first_after_failures", "must be ≥ 1"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.max_disagreement_chi2 > 0, "max_disagreement_chi2", "must be > 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.polish_max_frame_pixels >= 0, "polish_max_frame_pixels", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.polished_max_templates >= o.min_inliers && o.polished_max_templates <= 256,
            "polished_max_templates", "must be in [min_inliers, 256]"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.polish_min_frame_pixels >= 0, "polish_min_frame_pixels", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.polish_dense_max_frame_pixels >= 0, "polish_dense_max_frame_pixels", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.polish_dense_max_level_pixels >= 0, "polish_dense_max_level_pixels", "must be ≥ 0"));
  FLEETLOC_RETURN_IF_ERROR(
      Check(o.polish_dense_below_correlation >= 0 && o.polish_dense_below_correlation <= 1,
            "polish_dense_below_correlation", "must be in [0, 1]"));
  return Status::Ok();
}

Status ValidateOdometryNoise(const OdometryNoiseOptions& n) {
  FLEETLOC_RETURN_IF_ERROR(Check(
      n.along_sigma_per_m >= 0 && n.lateral_sigma_per_m >= 0 && n.heading_sigma_per_rad >= 0 &&
          n.heading_sigma_per_m >= 0 && n.heading_sigma_per_s >= 0 && n.floor_sigma_m > 0 &&
          n.extrapolation_accel_m_s2 >= 0 && n.extrapolation_angular_accel_rad_s2 >= 0,
      "odometry", "noise terms must be ≥ 0 (floor_sigma_m > 0)"));
  return Status::Ok();
}

}  // namespace

Status Validate(const DirectAlignOptions& d) {
  FLEETLOC_RETURN_IF_ERROR(ValidateDirectLevels(d));
  return ValidateDirectSearch(d);
}

TrackerOptions CountingTemplateInliers(TrackerOptions options) {
  options.polished_max_templates = options.max_templates;
  return options;
}

Status Validate(const TrackerOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(ValidateTemplates(o));
  FLEETLOC_RETURN_IF_ERROR(ValidateSearchAndFilter(o));
  FLEETLOC_RETURN_IF_ERROR(Validate(o.direct));
  return ValidateOdometryNoise(o.odometry);
}

}  // namespace fleetloc::tracking
