// The camera effects of the tracker stress suite's conditions (docs/benchmarks.md, "Tracker
// stress suite"), shared by `fleetctl bench tracker-stress`, `fleetctl bench reloc --stress` and
// the tests that need the same frames: clean, fast (short exposure, noise, gain jitter), dusty
// (dust, vignetting, uneven light, lens blur), all (fast and dusty), marks (held out: tyre
// marks, debris, the vehicle's shadow), camera (held out: another camera — JPEG, defocus, a
// harder response curve, motion blur) and aisles (clean frames along a route parallel to the
// mosaic's axes).
#pragma once

#include <optional>
#include <string>

#include "sim/sim_options.h"

namespace fleetloc::sim {

// The condition's camera effects on `fleetctl sim`'s defaults; exposure_s stays 0 (a short
// exposure depends on the vehicle's speed: the caller's). nullopt for an unknown condition.
std::optional<RenderOptions> StressCameraEffects(const std::string& condition);

// Whether the condition exposes briefly while the floor moves (fast, all).
bool StressConditionIsFast(const std::string& condition);

// The condition's route: the rounded rectangle, whose straights run along the mosaic's axes, for
// aisles (the camera's pixel grid then runs parallel to the mosaic's, as on a site mapped along its
// aisles), the figure eight otherwise.
RouteShape StressConditionRoute(const std::string& condition);

}  // namespace fleetloc::sim
