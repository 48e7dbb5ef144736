// The rooms generator of issue 16: a building with exactly the landmarks asked for, room by room;
// problems that see 3–6 corners of one room, with the asked share of outliers, a prior error
// within 0.3 m and 10° at the vehicle and a radius hint 1–3× the largest true displacement.
#include "mapmatch/room_map_problem.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "mapmatch/map_fit.h"

namespace fleetloc::mapmatch {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(RoomMap, HasTheAskedLandmarksEachInOneRoom) {
  for (const int count : {4, 30, 50}) {
    std::mt19937 rng(count);
    const RoomMap map = BuildRoomMap(count, rng);
    ASSERT_EQ(static_cast<int>(map.landmarks.size()), count);
    std::set<int> listed;
    for (const RoomMap::Room& room : map.rooms) {
      for (const int index : room.landmarks) {
        EXPECT_TRUE(listed.insert(index).second) << "landmark " << index << " in two rooms";
        const Eigen::Vector2d& m = map.landmarks[index];
        // Corners and jambs lie on the room's inner rectangle.
        const bool on_x =
            std::abs(m.x() - room.low.x()) < 1e-12 || std::abs(m.x() - room.high.x()) < 1e-12;
        const bool on_y =
            std::abs(m.y() - room.low.y()) < 1e-12 || std::abs(m.y() - room.high.y()) < 1e-12;
        EXPECT_TRUE(on_x || on_y);
      }
      const Eigen::Vector2d size = room.high - room.low;
      EXPECT_GE(size.minCoeff(), 2.7);
      EXPECT_LE(size.maxCoeff(), 6.0);
    }
    EXPECT_EQ(static_cast<int>(listed.size()), count);
    EXPECT_FALSE(FindDuplicateLandmarks(map.landmarks)) << "distinct positions";
  }
}

TEST(RoomProblem, SeesThreeToSixCornersAmongTheAskedOutliers) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const RoomMap map = BuildRoomMap(30, rng);
    const RoomProblem room = SimulateRoomProblem(map, {.outlier_fraction = 0.8}, rng);
    const MapFitProblem& p = room.problem;
    ASSERT_GE(room.seen.size(), 3u);
    ASSERT_LE(room.seen.size(), 6u);
    EXPECT_GE(p.inliers, 8 * static_cast<int>(room.seen.size()));
    EXPECT_LE(p.inliers, 12 * static_cast<int>(room.seen.size()));
    EXPECT_NEAR(1.0 - static_cast<double>(p.inliers) / p.points.size(), 0.8, 0.01);
    // At the vehicle the estimate is at most 0.3 m and 10° off.
    const Eigen::Vector2d at_vehicle = p.truth.Inverse() * room.vehicle - room.vehicle;
    EXPECT_LE(at_vehicle.norm(), 0.3 + 1e-9);
    EXPECT_LE(std::abs(p.truth.theta), 10 * kDeg);
    double largest = 0.0;
    for (const int index : room.seen) {
      const Eigen::Vector2d& m = map.landmarks[index];
      largest = std::max(largest, (p.truth.Inverse() * m - m).norm());
      // 8–12 points of σ = 1 cm observe it: most within 3 cm under the truth.
      const auto near = std::count_if(p.points.begin(), p.points.end(), [&](const auto& q) {
        return (p.truth * q - m).norm() < 0.03;
      });
      EXPECT_GE(near, 6) << "trial " << trial;
    }
    EXPECT_GE(room.radius_hint_m, largest - 1e-12);
    EXPECT_LE(room.radius_hint_m, 3.0 * largest + 1e-12);
  }
}

TEST(RoomProblem, TotalPointsIsExact) {
  std::mt19937 rng(3);
  const RoomMap map = BuildRoomMap(50, rng);
  for (const double fraction : {0.7, 0.9}) {
    const RoomProblem room =
        SimulateRoomProblem(map, {.outlier_fraction = fraction, .total_points = 200}, rng);
    EXPECT_EQ(room.problem.points.size(), 200u);
    EXPECT_EQ(room.problem.inliers, static_cast<int>(std::lround(200 * (1 - fraction))));
  }
}

}  // namespace
}  // namespace fleetloc::mapmatch
