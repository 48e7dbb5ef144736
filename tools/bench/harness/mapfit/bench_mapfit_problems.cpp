// The corridor and rooms problems of `fleetctl bench mapfit` (see bench_mapfit_problems.h).
#include "harness/mapfit/bench_mapfit_problems.h"

#include <cmath>

#include "mapmatch/room_map_problem.h"

namespace fleetloc::bench {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kCorridorRadiusM = 0.3;  // the corridor kind's kernel radius (issue 5)

// A 40 m corridor, 2.4 m wide: both ends and a door (two jambs) every ~5 m on each wall.
std::vector<Eigen::Vector2d> CorridorMap(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  std::vector<Eigen::Vector2d> map{{0, -1.2}, {0, 1.2}, {40, -1.2}, {40, 1.2}};
  for (double wall : {-1.2, 1.2}) {
    for (double x = 2.5; x < 38; x += 5.0) {
      const double door = x + jitter(rng);
      map.emplace_back(door, wall);
      map.emplace_back(door + 0.9, wall);
    }
  }
  return map;
}

// The vehicle somewhere in the corridor sees the landmarks within 4 m; its estimate is 2–5 cm and
// 1–2° off (a rotation about the vehicle, not the map origin).
MapFitTrial CorridorTrial(const std::vector<Eigen::Vector2d>& map, double outlier_fraction,
                          std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  MapFitTrial trial;
  trial.map = map;
  trial.radius_hint_m = kCorridorRadiusM;
  std::vector<int> observed;
  while (observed.size() < 2) {
    trial.vehicle = {2.0 + 36.0 * unit(rng), -0.3 + 0.6 * unit(rng)};
    observed.clear();
    for (std::size_t m = 0; m < map.size(); ++m)
      if ((map[m] - trial.vehicle).norm() < 4.0) observed.push_back(static_cast<int>(m));
  }
  const double heading = 2 * M_PI * unit(rng), shift = 0.02 + 0.03 * unit(rng);
  const double turn = (unit(rng) < 0.5 ? -1 : 1) * (1.0 + unit(rng)) * kDeg;
  const geometry::Pose2 at_vehicle{trial.vehicle.x(), trial.vehicle.y(), 0.0};
  const geometry::Pose2 error{shift * std::cos(heading), shift * std::sin(heading), turn};
  trial.problem = mapmatch::SimulateMapFitProblem(
      map, observed, at_vehicle * error * at_vehicle.Inverse(),
      {.points_per_landmark = 10, .noise_sigma_m = 0.01, .outlier_fraction = outlier_fraction},
      rng);
  return trial;
}

MapFitTrial RoomsTrial(const MapFitTrialOptions& options, std::mt19937& rng) {
  mapmatch::RoomMap building = mapmatch::BuildRoomMap(options.map_landmarks, rng);
  mapmatch::RoomProblem room = mapmatch::SimulateRoomProblem(
      building, {.outlier_fraction = options.outlier_fraction, .total_points = options.points},
      rng);
  MapFitTrial trial;
  trial.map = std::move(building.landmarks);
  trial.vehicle = room.vehicle;
  trial.problem = std::move(room.problem);
  trial.radius_hint_m = room.radius_hint_m;
  return trial;
}

}  // namespace

MapFitTrial MapFitTrials::Next(const MapFitTrialOptions& options) {
  if (options.kind == "rooms") return RoomsTrial(options, rng_);
  if (corridor_.empty()) corridor_ = CorridorMap(rng_);
  return CorridorTrial(corridor_, options.outlier_fraction, rng_);
}

std::string DescribeTrials(const MapFitTrialOptions& options) {
  if (options.kind == "rooms") {
    return "rooms: a new building of " + std::to_string(options.map_landmarks) +
           " landmarks (room corners, door jambs) per trial; the vehicle sees 3-6 corners of its "
           "room, 8-12 points (sigma 1 cm) each" +
           (options.points > 0 ? " (" + std::to_string(options.points) + " points in all)" : "") +
           "; outliers half uniform, half clustered (corner clutter, shelf legs); estimate up to "
           "0.3 m and 10 deg off; --radius a hint 1-3x the largest true displacement";
  }
  return "corridor: 36 landmarks (40 m x 2.4 m); 10 points (sigma 1 cm) per landmark within 4 m of "
         "the vehicle; uniform outliers; start 2-5 cm and 1-2 deg off; radius 0.3 m";
}

}  // namespace fleetloc::bench
