// Map-fit problems unlike the paper's figure 3 (issue 16): a building of rooms whose corners and
// door jambs are the landmark map; a vehicle in one room sees only 3–6 of them; its points are
// buried in uniform outliers and in clutter that looks like landmarks (clusters near the room's
// corners, the four legs of shelves); its pose estimate is off by up to 0.3 m and 10° about the
// vehicle, so the correction about the map origin can be a metre; and the kernel radius is only a
// hint, 1–3× the largest true displacement. Used by `fleetctl bench mapfit --kind rooms` and the
// robust map fit's tests.
#pragma once

#include <Eigen/Core>
#include <random>
#include <span>
#include <vector>

#include "mapmatch/map_fit_problem.h"

namespace fleetloc::mapmatch {

// A building of rectangular rooms on a grid (3–6 m × 3–5 m, walls 0.10–0.25 m thick): each room's
// four inner corners and, in some rooms, the two jambs of a door, room by room until `landmarks`
// (>= 4) are listed. Rooms look alike, so many landmark pairs share a distance.
struct RoomMap {
  std::vector<Eigen::Vector2d> landmarks;
  // Per room: its inner rectangle (low and high corner) and the indices of its landmarks.
  struct Room {
    Eigen::Vector2d low, high;
    std::vector<int> landmarks;
  };
  std::vector<Room> rooms;
};
RoomMap BuildRoomMap(int landmarks, std::mt19937& rng);

struct RoomProblemOptions {
  int min_seen = 3;  // landmarks of its room the vehicle sees (at most what the room has)
  int max_seen = 6;
  int min_points_per_landmark = 8;  // inliers per seen landmark
  int max_points_per_landmark = 12;
  double noise_sigma_m = 0.01;    // of an inlier, per axis
  double outlier_fraction = 0.8;  // of all points; in [0, 1)
  // Exactly this many points when > 0 (inliers (1 − outlier_fraction) of them, spread over the
  // seen landmarks); otherwise the inliers follow from points_per_landmark.
  int total_points = 0;
  double clustered_share = 0.5;    // of the outliers: in clusters (corner clutter, shelf legs)
  double max_prior_shift_m = 0.3;  // prior error at the vehicle, up to this
  double max_prior_turn_rad = 10 * M_PI / 180;  // ... and this
  double min_hint_factor = 1.0;  // radius hint: this to max_hint_factor × the largest true
  double max_hint_factor = 3.0;  // displacement of a seen landmark
};

struct RoomProblem {
  MapFitProblem problem;       // points (drifted frame), inlier count, true correction
  Eigen::Vector2d vehicle;     // where the vehicle is (map frame): errors are measured here
  std::vector<int> seen;       // indices of the landmarks its inliers observe
  double radius_hint_m = 0.0;  // the kernel radius a user would give
};

// One problem on `map`, deterministic for a given `rng` state. Options must be in range (checked:
// aborts otherwise — a bench or test bug).
RoomProblem SimulateRoomProblem(const RoomMap& map, const RoomProblemOptions& options,
                                std::mt19937& rng);

}  // namespace fleetloc::mapmatch
