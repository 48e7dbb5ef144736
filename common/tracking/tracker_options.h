// Options of the mosaic tracker, as typed data with units in the names, and their validation.
#pragma once

#include "base/status.h"

namespace fleetloc::tracking {

// Odometry noise model: the 1-sigma error of an odometry increment grows with the distance
// driven, the angle turned and the time elapsed.
struct OdometryNoiseOptions {
  double along_sigma_per_m = 0.012;       // distance scale error, metres per metre
  double lateral_sigma_per_m = 0.005;     // sideways slip, metres per metre
  double heading_sigma_per_rad = 0.012;   // turn scale error, radians per radian turned
  double heading_sigma_per_m = 0.003;     // heading error per metre driven
  double heading_sigma_per_s = 0.002;     // gyro-like drift, radians per second
  double floor_sigma_m = 1e-5;            // keeps the increment covariance positive definite
};

struct TrackerOptions {
  int template_size_px = 48;              // side of a square template (multiple of 4)
  int max_templates = 28;
  int min_inliers = 4;                    // fewer kept matches than this → coasting
  int candidate_step_px = 16;             // grid of template candidates in the frame
  int texture_window_px = 5;              // at half resolution
  double min_texture = 2.0;               // smallest eigenvalue, (grey levels/px)²
  double spread_sigma_px = 120.0;         // feature selection: distance scale of the spread bonus
  int normalize_window_px = 7;
  double min_peak_correlation = 0.4;
  double max_ambiguity_ratio = 0.92;      // second peak / best peak
  double min_peak_curvature = 0.005;      // NCC per px² at the peak; flatter peaks are rejected
  double search_sigma_multiple = 3.0;     // search window half-size = this × prediction sigma
  int min_search_radius_px = 3;
  int max_search_radius_px = 48;          // beyond this the prediction is too poor: lost
  int refine_search_radius_px = 2;        // fine passes around the previous solution
  int refine_passes = 0;                  // extra fine passes after the first
  // Coarse-to-fine: when the search radius exceeds coarse_above_radius_px, the first search runs
  // at pyramid level coarse_levels (each level halves the resolution and the radius) on the first
  // coarse_templates sites, each finer level refines ±refine radius, and the full-resolution
  // search only covers ±refine radius.
  int coarse_above_radius_px = 4;
  int coarse_levels = 2;
  int coarse_templates = 12;
  int coarse_template_size_px = 48;       // level-0 pixels (halved per level)
  double measurement_sigma_px = 0.15;     // 1-sigma of one template correspondence
  double outlier_ratio = 3.0;             // reject residual > ratio × median of the rest …
  double min_outlier_residual_px = 0.6;   // … and above this
  int max_coasting_frames = 50;           // after this many frames without a fix: lost
  int normalized_cache_mb = 128;          // normalized mosaic tiles (floats) kept in memory
  OdometryNoiseOptions odometry;
};

// Flat list of range checks; the message names the offending field.
Status Validate(const TrackerOptions& options);

}  // namespace fleetloc::tracking
