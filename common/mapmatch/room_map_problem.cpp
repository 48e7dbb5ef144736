// Room maps and cluttered map-fit problems on them (see room_map_problem.h).
#include "mapmatch/room_map_problem.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "base/status.h"

namespace fleetloc::mapmatch {
namespace {

double Uniform(double low, double high, std::mt19937& rng) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}

int UniformInt(int low, int high, std::mt19937& rng) {
  return std::uniform_int_distribution<int>(low, high)(rng);
}

// The two jambs of a door 0.8–1.0 m wide somewhere along one wall of the inner rectangle.
std::vector<Eigen::Vector2d> DoorJambs(const Eigen::Vector2d& low, const Eigen::Vector2d& high,
                                       std::mt19937& rng) {
  const int wall = UniformInt(0, 3, rng);  // bottom, top, left, right
  const bool horizontal = wall < 2;
  const double length = horizontal ? high.x() - low.x() : high.y() - low.y();
  const double width = Uniform(0.8, 1.0, rng);
  const double start = Uniform(0.3, length - 0.3 - width, rng);
  std::vector<Eigen::Vector2d> jambs;
  for (const double along : {start, start + width}) {
    if (horizontal)
      jambs.emplace_back(low.x() + along, wall == 0 ? low.y() : high.y());
    else
      jambs.emplace_back(wall == 2 ? low.x() : high.x(), low.y() + along);
  }
  return jambs;
}

// Appends `cluster` points around `center` with normal noise `sigma` (map frame).
void AddCluster(const Eigen::Vector2d& center, int count, double sigma, std::mt19937& rng,
                std::vector<Eigen::Vector2d>* out) {
  std::normal_distribution<double> noise(0.0, sigma);
  for (int k = 0; k < count; ++k) out->push_back(center + Eigen::Vector2d(noise(rng), noise(rng)));
}

// Clutter that looks like landmarks, `count` points in all: clusters of 3–10 points, half a corner
// clutter (a box 0.1–0.5 m from one of the room's landmarks, into the room), half the four legs of
// a shelf (0.4–1.2 m × 0.3–0.6 m, any orientation) standing in the room.
std::vector<Eigen::Vector2d> ClusteredOutliers(const RoomMap& map, const RoomMap::Room& room,
                                               int count, std::mt19937& rng) {
  std::vector<Eigen::Vector2d> out;
  const Eigen::Vector2d middle = 0.5 * (room.low + room.high);
  std::vector<Eigen::Vector2d> centers;
  while (static_cast<int>(out.size()) < count) {
    centers.clear();
    if (UniformInt(0, 1, rng) == 0) {
      const Eigen::Vector2d& corner =
          map.landmarks[room.landmarks[UniformInt(0, room.landmarks.size() - 1, rng)]];
      const double inward = std::atan2(middle.y() - corner.y(), middle.x() - corner.x());
      const double angle = inward + Uniform(-M_PI / 4, M_PI / 4, rng);
      centers.emplace_back(corner + Uniform(0.1, 0.5, rng) *
                                        Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    } else {
      const Eigen::Vector2d at(Uniform(room.low.x() + 0.7, room.high.x() - 0.7, rng),
                               Uniform(room.low.y() + 0.7, room.high.y() - 0.7, rng));
      const Eigen::Rotation2Dd turn(Uniform(-M_PI, M_PI, rng));
      const double a = 0.5 * Uniform(0.4, 1.2, rng), b = 0.5 * Uniform(0.3, 0.6, rng);
      for (const Eigen::Vector2d& leg : {Eigen::Vector2d(-a, -b), Eigen::Vector2d(a, -b),
                                         Eigen::Vector2d(a, b), Eigen::Vector2d(-a, b)})
        centers.emplace_back(at + turn * leg);
    }
    for (const Eigen::Vector2d& center : centers) {
      const int size = std::min(UniformInt(3, 10, rng), count - static_cast<int>(out.size()));
      AddCluster(center, size, Uniform(0.005, 0.02, rng), rng, &out);
    }
  }
  return out;
}

// Inliers per seen landmark: each its own random count, or `total` spread as evenly as possible.
std::vector<int> InlierCounts(int seen, int total, const RoomProblemOptions& o, std::mt19937& rng) {
  std::vector<int> counts(seen);
  for (int& n : counts) n = UniformInt(o.min_points_per_landmark, o.max_points_per_landmark, rng);
  if (total <= 0) return counts;
  for (int k = 0; k < seen; ++k) counts[k] = total / seen + (k < total % seen ? 1 : 0);
  std::shuffle(counts.begin(), counts.end(), rng);
  return counts;
}

// The `wanted` landmarks of `room` nearest to `vehicle`.
std::vector<int> NearestOfRoom(const RoomMap& map, const RoomMap::Room& room,
                               const Eigen::Vector2d& vehicle, int wanted) {
  std::vector<int> order = room.landmarks;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return (map.landmarks[a] - vehicle).squaredNorm() < (map.landmarks[b] - vehicle).squaredNorm();
  });
  order.resize(std::min<std::size_t>(order.size(), wanted));
  return order;
}

void CheckOptions(const RoomProblemOptions& o) {
  FLEETLOC_CHECK(o.min_seen >= 2 && o.min_seen <= o.max_seen);
  FLEETLOC_CHECK(o.min_points_per_landmark >= 1 &&
                 o.min_points_per_landmark <= o.max_points_per_landmark);
  FLEETLOC_CHECK(o.noise_sigma_m >= 0 && o.outlier_fraction >= 0 && o.outlier_fraction < 1);
  FLEETLOC_CHECK(o.total_points >= 0 && o.clustered_share >= 0 && o.clustered_share <= 1);
  FLEETLOC_CHECK(o.max_prior_shift_m >= 0 && o.max_prior_turn_rad >= 0);
  FLEETLOC_CHECK(o.min_hint_factor > 0 && o.min_hint_factor <= o.max_hint_factor);
}

}  // namespace

RoomMap BuildRoomMap(int landmarks, std::mt19937& rng) {
  FLEETLOC_CHECK(landmarks >= 4);
  RoomMap map;
  const int columns = std::max(2, static_cast<int>(std::lround(std::sqrt(landmarks / 5.0))));
  const double wall = Uniform(0.10, 0.25, rng);
  std::vector<double> x_walls{0.0};
  for (int c = 0; c < columns; ++c) x_walls.push_back(x_walls.back() + Uniform(3.0, 6.0, rng));
  double row_low = 0.0, row_high = Uniform(3.0, 5.0, rng);
  for (int index = 0; static_cast<int>(map.landmarks.size()) < landmarks; ++index) {
    const int column = index % columns;
    if (column == 0 && index > 0) {
      row_low = row_high;
      row_high += Uniform(3.0, 5.0, rng);
    }
    RoomMap::Room room;
    room.low = {x_walls[column] + wall / 2, row_low + wall / 2};
    room.high = {x_walls[column + 1] - wall / 2, row_high - wall / 2};
    std::vector<Eigen::Vector2d> corners{
        room.low, {room.high.x(), room.low.y()}, room.high, {room.low.x(), room.high.y()}};
    if (UniformInt(0, 1, rng) == 1) {
      for (const Eigen::Vector2d& jamb : DoorJambs(room.low, room.high, rng))
        corners.push_back(jamb);
    }
    for (const Eigen::Vector2d& corner : corners) {
      if (static_cast<int>(map.landmarks.size()) == landmarks) break;
      room.landmarks.push_back(static_cast<int>(map.landmarks.size()));
      map.landmarks.push_back(corner);
    }
    map.rooms.push_back(std::move(room));
  }
  return map;
}

RoomProblem SimulateRoomProblem(const RoomMap& map, const RoomProblemOptions& options,
                                std::mt19937& rng) {
  CheckOptions(options);
  std::vector<int> candidates;  // rooms with enough landmarks to see min_seen of them
  for (std::size_t r = 0; r < map.rooms.size(); ++r)
    if (static_cast<int>(map.rooms[r].landmarks.size()) >= options.min_seen)
      candidates.push_back(static_cast<int>(r));
  FLEETLOC_CHECK(!candidates.empty());
  const RoomMap::Room& room = map.rooms[candidates[UniformInt(0, candidates.size() - 1, rng)]];

  RoomProblem out;
  out.vehicle = {Uniform(room.low.x() + 0.5, room.high.x() - 0.5, rng),
                 Uniform(room.low.y() + 0.5, room.high.y() - 0.5, rng)};
  out.seen =
      NearestOfRoom(map, room, out.vehicle, UniformInt(options.min_seen, options.max_seen, rng));
  // The estimate is off by a shift and a turn about the vehicle.
  const double shift = options.max_prior_shift_m * Uniform(0, 1, rng);
  const double heading = Uniform(-M_PI, M_PI, rng);
  const double turn = Uniform(-options.max_prior_turn_rad, options.max_prior_turn_rad, rng);
  const geometry::Pose2 at_vehicle{out.vehicle.x(), out.vehicle.y(), 0.0};
  const geometry::Pose2 error{shift * std::cos(heading), shift * std::sin(heading), turn};
  MapFitProblem& problem = out.problem;
  problem.truth = at_vehicle * error * at_vehicle.Inverse();
  const geometry::Pose2 drift = problem.truth.Inverse();

  std::vector<Eigen::Vector2d> map_points;  // in the map frame, drifted at the end
  const int total = options.total_points;
  const int inliers_wanted =
      total > 0 ? static_cast<int>(std::lround(total * (1.0 - options.outlier_fraction))) : 0;
  const std::vector<int> counts =
      InlierCounts(static_cast<int>(out.seen.size()), inliers_wanted, options, rng);
  double largest_displacement = 0.0;
  for (std::size_t k = 0; k < out.seen.size(); ++k) {
    const Eigen::Vector2d& landmark = map.landmarks[out.seen[k]];
    AddCluster(landmark, counts[k], options.noise_sigma_m, rng, &map_points);
    largest_displacement = std::max(largest_displacement, (drift * landmark - landmark).norm());
  }
  problem.inliers = static_cast<int>(map_points.size());
  const double f = options.outlier_fraction;
  const int outliers = total > 0 ? total - problem.inliers
                                 : static_cast<int>(std::lround(problem.inliers * f / (1.0 - f)));
  const int clustered = static_cast<int>(std::lround(outliers * options.clustered_share));
  for (const Eigen::Vector2d& p : ClusteredOutliers(map, room, clustered, rng))
    map_points.push_back(p);
  const Eigen::Vector2d low = room.low.array() - 0.5, high = room.high.array() + 0.5;
  for (int k = clustered; k < outliers; ++k)
    map_points.emplace_back(Uniform(low.x(), high.x(), rng), Uniform(low.y(), high.y(), rng));

  for (const Eigen::Vector2d& p : map_points) problem.points.push_back(drift * p);
  std::shuffle(problem.points.begin(), problem.points.end(), rng);
  out.radius_hint_m =
      Uniform(options.min_hint_factor, options.max_hint_factor, rng) * largest_displacement;
  return out;
}

}  // namespace fleetloc::mapmatch
