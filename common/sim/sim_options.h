// Options of the vehicle-run simulator: route, timing, odometry errors, initial pose and camera
// rendering effects, as typed data with one flat validation function.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <optional>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::sim {

enum class RouteShape {
  kFigureEight,       // Lissajous 1:2 figure eight: turns both ways, crosses itself (revisits)
  kRoundedRectangle,  // superellipse |x|^4 + |y|^4 = 1: one turning direction, long straights
};

// The closed route of the camera footprint centre over the floor.
struct RouteOptions {
  RouteShape shape = RouteShape::kFigureEight;
  double speed_px_s = 3000.0;             // footprint speed over the floor, floor pixels per s
  double speed_variation_fraction = 0.0;  // speed = v · (1 + f · sin(2π t / period)), f < 1
  double speed_variation_period_s = 8.0;
  double crab_rad = 0.0;                    // vehicle heading minus direction of travel
  double min_floor_overlap_fraction = 0.6;  // share of every frame's footprint on the floor
  double start_fraction = 0.0;              // start point as a fraction of the route length
};

// Sampling times of frames and odometry. Frame i is captured at
// start_time_s + frame_delay_s + i / frame_rate_hz (+ jitter); odometry starts at start_time_s and
// ends one odometry period after the last frame.
struct TimingOptions {
  int frames = 100;
  double frame_rate_hz = 5.0;
  double odometry_rate_hz = 100.0;
  double start_time_s = 0.0;
  double frame_delay_s = 0.05;    // first frame after the first odometry sample
  double frame_jitter_s = 0.001;  // uniform ± on each frame's capture time
  double odometry_jitter_s = 0.0005;
};

// Wheel-odometry-like errors applied to the true base_link increments.
struct OdometryOptions {
  double distance_scale_error = 0.01;               // odometry distance = true distance · (1 + e)
  double heading_scale_error = 0.01;                // odometry turn = true turn · (1 + e)
  double heading_drift_rad_s = 0.2 * M_PI / 180.0;  // gyro-like heading bias
  double distance_noise_m_per_sqrt_m = 0.0005;      // white noise, random walk in distance
  double heading_noise_rad_per_sqrt_s = 0.0005;     // white noise, random walk in heading
  // The odom pose at the first odometry sample; when absent, truth there (odom starts aligned).
  std::optional<geometry::Pose2> start_pose;
};

// run.json's initial_pose: truth at the first frame, perturbed by a draw from `sigma`.
struct InitialPoseOptions {
  Eigen::Vector3d sigma{0.002, 0.002, 0.5 * M_PI / 180.0};  // x_m, y_m, theta_rad (1-sigma)
  bool perturb = true;
};

// The camera renderer's sampling and photometric effects, in the order they are applied.
// Dust sizes are in camera pixels; intensities in DN (0..255).
struct RenderOptions {
  int supersample = 3;          // area-sensor sampling: mean of k × k bilinear samples per pixel
  double floor_grain_dn = 2.0;  // floor-attached pixel noise the mosaic lacks (its capture noise)
  double dust_fraction = 0.08;  // share of the floor covered by dust and grime blobs
  double dust_min_radius_px = 2.0;  // blob semi-major axis, log-uniform in [min, max]
  double dust_max_radius_px = 20.0;
  double dust_streak_fraction = 0.3;  // share of blobs that are thin streaks
  double dust_max_opacity = 0.7;      // opacity drawn uniformly in [0.2, max]
  // Other occluders (off by default): tyre marks (curved bands with a tread) and hard-edged
  // debris on the floor, each as a share of the floor covered; the vehicle's own shadow over a
  // share of the frame beyond a straight soft edge (its direction fixed per run), darkening by
  // shadow_depth.
  double tyre_mark_fraction = 0.0;
  double debris_fraction = 0.0;
  double shadow_fraction = 0.0;
  double shadow_depth = 0.5;
  double shadow_edge_px = 6.0;          // penumbra width
  double lighting_amplitude = 0.15;     // relative amplitude of the low-frequency light field
  double blur_sigma_px = 0.7;           // lens blur (Gaussian)
  double exposure_s = 0.0;              // motion blur along travel; 0 = none
  double vignetting_corner_loss = 0.2;  // cos^4 falloff: brightness lost at the image corners
  double gain_min = 0.85;               // per-frame gain drawn uniformly in [min, max]
  double gain_max = 1.15;
  double shot_noise_dn = 0.1;      // shot-noise variance per DN of signal
  double noise_sigma_dn = 2.0;     // read noise (Gaussian) standard deviation
  double response_gamma = 0.85;    // camera response: x^gamma blended with an S-curve
  double response_s_curve = 0.25;  // blend weight of smoothstep, 0..1
  double bias_min_dn = -8.0;       // per-frame bias (black level) in [min, max]
  double bias_max_dn = 8.0;
  // The camera's compression: each frame JPEG-encoded at this quality (1..100) and decoded, as a
  // camera that streams JPEG (MJPEG) delivers it, with its 8 × 8 block artifacts; 0: none.
  int jpeg_quality = 0;
};

// A kidnapped vehicle: at `at_s` after the start it is picked up and set down `jump_fraction` of
// a lap further along the route. The frames show the new place from then on; the wheels never
// turned, so the odometry continues smoothly through the jump (it cannot see it).
struct KidnapOptions {
  double at_s = -1.0;          // elapsed time of the jump; negative: never
  double jump_fraction = 0.5;  // how far along the route, as a fraction of its length
  bool enabled() const { return at_s >= 0.0; }
};

struct SimOptions {
  RouteOptions route;
  KidnapOptions kidnap;
  TimingOptions timing;
  OdometryOptions odometry;
  InitialPoseOptions initial_pose;
  RenderOptions render;
  std::uint64_t seed = 1;  // every random draw derives from it: same seed, same run
};

// Flat list of range checks; InvalidInput naming the first offending field.
Status Validate(const SimOptions& options);

// The render options with every photometric effect off (supersampling kept): a pure resampling of
// the floor, for debugging and geometry tests.
RenderOptions CleanRenderOptions(RenderOptions options);

// Everything off: clean rendering, exact odometry, no timing jitter, unperturbed initial pose.
SimOptions CleanSimOptions(SimOptions options);

}  // namespace fleetloc::sim
