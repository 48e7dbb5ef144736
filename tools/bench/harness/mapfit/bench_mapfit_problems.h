// The problems `fleetctl bench mapfit` runs the map fits on, one kind per generator: `corridor`
// (issue 5: a 36-landmark corridor, the landmarks within 4 m seen, uniform outliers, a start a few
// centimetres and degrees off, kernel radius 0.3 m) and `rooms` (issue 16, mapmatch/
// room_map_problem.h: 3–6 corners of a ~30-landmark building seen, uniform and clustered outliers,
// up to 0.3 m and 10° off, the kernel radius a hint 1–3× the largest true displacement).
#pragma once

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "mapmatch/map_fit_problem.h"

namespace fleetloc::bench {

struct MapFitTrial {
  std::vector<Eigen::Vector2d> map;  // the landmark map the points are fitted to
  Eigen::Vector2d vehicle;           // errors are measured at the vehicle
  mapmatch::MapFitProblem problem;
  double radius_hint_m = 0.0;  // the kernel radius --radius a user would give
};

struct MapFitTrialOptions {
  std::string kind = "corridor";  // "corridor" or "rooms"
  double outlier_fraction = 0.7;
  int map_landmarks = 30;  // rooms: landmarks in the building
  int points = 0;          // rooms: exactly this many points per problem when > 0
};

// A stream of trials from one seed: the corridor kind draws its map once (the first call), the
// rooms kind a new building per trial.
class MapFitTrials {
 public:
  explicit MapFitTrials(unsigned seed) : rng_(seed) {}
  MapFitTrial Next(const MapFitTrialOptions& options);

 private:
  std::mt19937 rng_;
  std::vector<Eigen::Vector2d> corridor_;  // drawn on first use
};

// One line describing the problems of `options.kind` for the bench's header.
std::string DescribeTrials(const MapFitTrialOptions& options);

}  // namespace fleetloc::bench
