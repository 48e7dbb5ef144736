// Camera effects of the stress suite's conditions (see stress_camera.h).
#include "sim/stress_camera.h"

namespace fleetloc::sim {
namespace {

// Occluders of other shapes than the dust the tracker was tuned under (held out: never used while
// tuning): tyre marks, hard-edged debris and the vehicle's own shadow, with milder vignetting and
// light than "dusty".
RenderOptions MarksEffects() {
  RenderOptions r;
  r.dust_fraction = 0.0;
  r.tyre_mark_fraction = 0.12;
  r.debris_fraction = 0.05;
  r.shadow_fraction = 0.3;
  r.shadow_depth = 0.6;
  r.vignetting_corner_loss = 0.3;
  r.lighting_amplitude = 0.2;
  r.gain_min = 0.8;
  r.gain_max = 1.2;
  return r;
}

// Another camera (held out: never used while tuning): it streams JPEG (quality 70, 8 × 8 block
// artifacts), its lens is a little out of focus (σ 1 px) and vignettes 35 %, its response curve is
// harder (γ 0.6, S-curve 0.6), and its exposure is long enough for the floor to sweep about 4 px
// (the caller's: it depends on the speed). Read noise 2.5 DN, gain ±15 %, bias ±10 DN.
RenderOptions OtherCameraEffects() {
  RenderOptions r;
  r.dust_fraction = 0.0;
  r.jpeg_quality = 70;
  r.blur_sigma_px = 1.0;
  r.vignetting_corner_loss = 0.35;
  r.lighting_amplitude = 0.1;
  r.response_gamma = 0.6;
  r.response_s_curve = 0.6;
  r.noise_sigma_dn = 2.5;
  r.shot_noise_dn = 0.15;
  r.gain_min = 0.85;
  r.gain_max = 1.15;
  r.bias_min_dn = -10.0;
  r.bias_max_dn = 10.0;
  return r;
}

}  // namespace

bool StressConditionIsFast(const std::string& condition) {
  return condition == "fast" || condition == "all";
}

RouteShape StressConditionRoute(const std::string& condition) {
  return condition == "aisles" ? RouteShape::kRoundedRectangle : RouteShape::kFigureEight;
}

std::optional<RenderOptions> StressCameraEffects(const std::string& condition) {
  if (condition == "marks") return MarksEffects();
  if (condition == "camera") return OtherCameraEffects();
  if (condition == "aisles") return StressCameraEffects("clean");
  if (condition != "clean" && !StressConditionIsFast(condition) && condition != "dusty")
    return std::nullopt;
  const bool fast = StressConditionIsFast(condition);
  const bool dusty = condition == "dusty" || condition == "all";
  RenderOptions r;  // `fleetctl sim`'s defaults, then the condition
  r.dust_fraction = dusty ? 0.3 : 0.0;
  r.dust_max_radius_px = dusty ? 40.0 : r.dust_max_radius_px;
  r.dust_streak_fraction = dusty ? 0.5 : r.dust_streak_fraction;
  r.dust_max_opacity = dusty ? 0.9 : r.dust_max_opacity;
  r.vignetting_corner_loss = dusty ? 0.5 : 0.05;
  r.lighting_amplitude = dusty ? 0.4 : 0.03;
  r.blur_sigma_px = dusty ? 1.5 : 0.5;
  const bool jitter = fast || dusty;
  r.gain_min = jitter ? 0.75 : 0.97;
  r.gain_max = jitter ? 1.25 : 1.03;
  r.bias_min_dn = dusty ? -20.0 : -2.0;
  r.bias_max_dn = dusty ? 20.0 : 2.0;
  r.noise_sigma_dn = fast ? 4.0 : 1.0;
  r.shot_noise_dn = fast ? 0.3 : 0.05;
  return r;
}

}  // namespace fleetloc::sim
