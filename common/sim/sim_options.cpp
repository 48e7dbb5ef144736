// Validation and "clean" presets of the simulator options.
#include "sim/sim_options.h"

#include <sstream>
#include <string>

namespace fleetloc::sim {
namespace {

std::string Num(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Collects the first failed range check with the field's name.
class Checker {
 public:
  void Range(const char* field, double value, double lo, double hi) {
    if (!status_.ok()) return;
    if (!std::isfinite(value) || value < lo || value > hi) {
      status_ = InvalidInput("sim option '" + std::string(field) + "' = " + Num(value) +
                             " is outside [" + Num(lo) + ", " + Num(hi) + "]");
    }
  }
  void Ordered(const char* lo_field, double lo, const char* hi_field, double hi) {
    if (status_.ok() && lo > hi) {
      status_ = InvalidInput("sim option '" + std::string(lo_field) + "' exceeds '" +
                             std::string(hi_field) + "'");
    }
  }
  Status status() const { return status_; }

 private:
  Status status_;
};

void CheckRoute(const RouteOptions& r, Checker* c) {
  c->Range("speed_px_s", r.speed_px_s, 1e-3, 1e6);
  c->Range("speed_variation_fraction", r.speed_variation_fraction, 0.0, 0.9);
  c->Range("speed_variation_period_s", r.speed_variation_period_s, 1e-3, 1e6);
  c->Range("crab_rad", r.crab_rad, -M_PI / 2, M_PI / 2);
  c->Range("min_floor_overlap_fraction", r.min_floor_overlap_fraction, 0.0, 1.0);
  c->Range("start_fraction", r.start_fraction, 0.0, 1.0);
}

void CheckKidnap(const KidnapOptions& k, Checker* c) {
  if (!k.enabled()) return;
  c->Range("kidnap_at_s", k.at_s, 0.0, 1e9);
  c->Range("kidnap_jump_fraction", k.jump_fraction, 0.01, 0.99);
}

void CheckTiming(const TimingOptions& t, Checker* c) {
  c->Range("frames", t.frames, 1, 1e7);
  c->Range("frame_rate_hz", t.frame_rate_hz, 1e-3, 1000.0);
  c->Range("odometry_rate_hz", t.odometry_rate_hz, t.frame_rate_hz, 10000.0);
  c->Range("start_time_s", t.start_time_s, -1e12, 1e12);
  c->Range("frame_delay_s", t.frame_delay_s, 0.0, 1e6);
  // Jitter below a quarter period keeps the times strictly ascending.
  c->Range("frame_jitter_s", t.frame_jitter_s, 0.0, 0.25 / t.frame_rate_hz);
  c->Range("odometry_jitter_s", t.odometry_jitter_s, 0.0, 0.25 / t.odometry_rate_hz);
}

void CheckOdometry(const OdometryOptions& o, const InitialPoseOptions& i, Checker* c) {
  c->Range("distance_scale_error", o.distance_scale_error, -0.5, 0.5);
  c->Range("heading_scale_error", o.heading_scale_error, -0.5, 0.5);
  c->Range("heading_drift_rad_s", o.heading_drift_rad_s, -1.0, 1.0);
  c->Range("distance_noise_m_per_sqrt_m", o.distance_noise_m_per_sqrt_m, 0.0, 1.0);
  c->Range("heading_noise_rad_per_sqrt_s", o.heading_noise_rad_per_sqrt_s, 0.0, 1.0);
  c->Range("initial_sigma_x_m", i.sigma.x(), 0.0, 100.0);
  c->Range("initial_sigma_y_m", i.sigma.y(), 0.0, 100.0);
  c->Range("initial_sigma_theta_rad", i.sigma.z(), 0.0, M_PI);
}

void CheckRender(const RenderOptions& r, Checker* c) {
  c->Range("supersample", r.supersample, 1, 8);
  c->Range("floor_grain_dn", r.floor_grain_dn, 0.0, 50.0);
  c->Range("dust_fraction", r.dust_fraction, 0.0, 0.9);
  c->Range("dust_min_radius_px", r.dust_min_radius_px, 0.5, 1000.0);
  c->Range("dust_max_radius_px", r.dust_max_radius_px, 0.5, 1000.0);
  c->Ordered("dust_min_radius_px", r.dust_min_radius_px, "dust_max_radius_px",
             r.dust_max_radius_px);
  c->Range("dust_streak_fraction", r.dust_streak_fraction, 0.0, 1.0);
  c->Range("dust_max_opacity", r.dust_max_opacity, 0.2, 1.0);
  c->Range("tyre_mark_fraction", r.tyre_mark_fraction, 0.0, 0.9);
  c->Range("debris_fraction", r.debris_fraction, 0.0, 0.9);
  c->Range("shadow_fraction", r.shadow_fraction, 0.0, 0.9);
  c->Range("shadow_depth", r.shadow_depth, 0.0, 0.95);
  c->Range("shadow_edge_px", r.shadow_edge_px, 0.0, 1000.0);
  c->Range("lighting_amplitude", r.lighting_amplitude, 0.0, 0.9);
  c->Range("blur_sigma_px", r.blur_sigma_px, 0.0, 20.0);
  c->Range("exposure_s", r.exposure_s, 0.0, 1.0);
  c->Range("vignetting_corner_loss", r.vignetting_corner_loss, 0.0, 0.9);
  c->Range("gain_min", r.gain_min, 0.01, 100.0);
  c->Range("gain_max", r.gain_max, 0.01, 100.0);
  c->Ordered("gain_min", r.gain_min, "gain_max", r.gain_max);
  c->Range("shot_noise_dn", r.shot_noise_dn, 0.0, 100.0);
  c->Range("noise_sigma_dn", r.noise_sigma_dn, 0.0, 100.0);
  c->Range("response_gamma", r.response_gamma, 0.2, 5.0);
  c->Range("response_s_curve", r.response_s_curve, 0.0, 1.0);
  c->Range("bias_min_dn", r.bias_min_dn, -255.0, 255.0);
  c->Range("bias_max_dn", r.bias_max_dn, -255.0, 255.0);
  c->Ordered("bias_min_dn", r.bias_min_dn, "bias_max_dn", r.bias_max_dn);
  c->Range("jpeg_quality", r.jpeg_quality, 0, 100);
}

}  // namespace

Status Validate(const SimOptions& options) {
  Checker c;
  CheckRoute(options.route, &c);
  CheckKidnap(options.kidnap, &c);
  CheckTiming(options.timing, &c);
  CheckOdometry(options.odometry, options.initial_pose, &c);
  CheckRender(options.render, &c);
  return c.status();
}

RenderOptions CleanRenderOptions(RenderOptions o) {
  o.floor_grain_dn = 0.0;
  o.dust_fraction = 0.0;
  o.tyre_mark_fraction = 0.0;
  o.debris_fraction = 0.0;
  o.shadow_fraction = 0.0;
  o.lighting_amplitude = 0.0;
  o.blur_sigma_px = 0.0;
  o.exposure_s = 0.0;
  o.vignetting_corner_loss = 0.0;
  o.gain_min = o.gain_max = 1.0;
  o.shot_noise_dn = 0.0;
  o.noise_sigma_dn = 0.0;
  o.response_gamma = 1.0;
  o.response_s_curve = 0.0;
  o.bias_min_dn = o.bias_max_dn = 0.0;
  o.jpeg_quality = 0;
  return o;
}

SimOptions CleanSimOptions(SimOptions o) {
  o.render = CleanRenderOptions(o.render);
  o.timing.frame_jitter_s = 0.0;
  o.timing.odometry_jitter_s = 0.0;
  o.odometry.distance_scale_error = 0.0;
  o.odometry.heading_scale_error = 0.0;
  o.odometry.heading_drift_rad_s = 0.0;
  o.odometry.distance_noise_m_per_sqrt_m = 0.0;
  o.odometry.heading_noise_rad_per_sqrt_s = 0.0;
  o.initial_pose.perturb = false;
  return o;
}

}  // namespace fleetloc::sim
