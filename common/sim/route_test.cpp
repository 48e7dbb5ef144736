// Tests for the simulated route: it stays over the floor, runs at the requested speed and heads
// along its direction of travel.
#include "sim/route.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim_test_util.h"

namespace fleetloc::sim {
namespace {

using testing::kResolutionM;
using testing::SmallCamera;

// The 512×512 px test floor at 0.5 mm/px with its top-left corner at map (1, 2).
geometry::ConvexPolygon TestFloor() {
  return geometry::Rectangle(1.0, 2.0 - 512 * kResolutionM, 1.0 + 512 * kResolutionM, 2.0);
}

geometry::ConvexPolygon SmallFootprint() {
  return FootprintInGround(SmallCamera());  // the mount does not change the footprint
}

class RouteShapes : public ::testing::TestWithParam<RouteShape> {};

TEST_P(RouteShapes, EveryFrameKeepsTheRequiredShareOnTheFloor) {
  RouteOptions options;
  options.shape = GetParam();
  options.min_floor_overlap_fraction = 0.6;
  const Result<Route> route = Route::Fit(TestFloor(), SmallFootprint(), options, kResolutionM);
  ASSERT_TRUE(route.ok()) << route.status().message();
  // Checked far more densely than the fit did (every 0.1 px of route).
  const int samples = static_cast<int>(route->length_m() / (0.1 * kResolutionM));
  EXPECT_GE(route->MinFloorOverlap(TestFloor(), SmallFootprint(), samples), 0.6 - 1e-3);
  // And the fit is tight: the route uses the floor, it does not hide in the middle.
  EXPECT_LT(route->MinFloorOverlap(TestFloor(), SmallFootprint(), samples), 0.7);
  for (int i = 0; i < 1000; ++i) {
    const geometry::Pose2 pose = route->CameraPoseAtArcLength(route->length_m() * i / 1000);
    EXPECT_TRUE(geometry::Contains(TestFloor(), {pose.x, pose.y}));
  }
}

TEST_P(RouteShapes, ConstantSpeedMatchesTheRequestedPixelsPerSecond) {
  RouteOptions options;
  options.shape = GetParam();
  options.speed_px_s = 3000.0;
  const Result<Route> route = Route::Fit(TestFloor(), SmallFootprint(), options, kResolutionM);
  ASSERT_TRUE(route.ok());
  const double dt = 1e-3;
  for (double t = 0.0; t < 2.0; t += 0.0137) {
    const geometry::Pose2 a = route->CameraPoseAt(t), b = route->CameraPoseAt(t + dt);
    const double speed_px_s = std::hypot(b.x - a.x, b.y - a.y) / dt / kResolutionM;
    EXPECT_NEAR(speed_px_s, 3000.0, 3000.0 * 2e-3) << "t = " << t;
  }
}

TEST_P(RouteShapes, HeadingIsTheDirectionOfTravelPlusCrab) {
  RouteOptions options;
  options.shape = GetParam();
  options.crab_rad = 0.1;
  const Result<Route> route = Route::Fit(TestFloor(), SmallFootprint(), options, kResolutionM);
  ASSERT_TRUE(route.ok());
  for (double t = 0.0; t < 1.0; t += 0.01) {
    const geometry::Pose2 a = route->CameraPoseAt(t - 1e-4), b = route->CameraPoseAt(t + 1e-4);
    const geometry::Pose2 mid = route->CameraPoseAt(t);
    const double travel = std::atan2(b.y - a.y, b.x - a.x);
    EXPECT_NEAR(geometry::WrapAngle(mid.theta - travel - 0.1), 0.0, 1e-4) << "t = " << t;
  }
}

TEST_P(RouteShapes, IsClosed) {
  RouteOptions options;
  options.shape = GetParam();
  const Result<Route> route = Route::Fit(TestFloor(), SmallFootprint(), options, kResolutionM);
  ASSERT_TRUE(route.ok());
  const geometry::Pose2 start = route->CameraPoseAtArcLength(0.0);
  const geometry::Pose2 lap = route->CameraPoseAtArcLength(route->length_m());
  EXPECT_NEAR(start.x, lap.x, 1e-9);
  EXPECT_NEAR(start.y, lap.y, 1e-9);
  EXPECT_NEAR(geometry::WrapAngle(start.theta - lap.theta), 0.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Shapes, RouteShapes,
                         ::testing::Values(RouteShape::kFigureEight,
                                           RouteShape::kRoundedRectangle));

TEST(Route, SpeedVariationAveragesToTheNominalSpeedOverAPeriod) {
  RouteOptions options;
  options.speed_px_s = 2000.0;
  options.speed_variation_fraction = 0.3;
  options.speed_variation_period_s = 4.0;
  const Result<Route> route = Route::Fit(TestFloor(), SmallFootprint(), options, kResolutionM);
  ASSERT_TRUE(route.ok());
  EXPECT_NEAR(route->ArcLengthAt(4.0) - route->ArcLengthAt(0.0), 4.0 * 2000.0 * kResolutionM, 1e-9);
  EXPECT_NEAR(route->SpeedAt(1.0), 1.3 * 2000.0 * kResolutionM, 1e-9);  // the peak
  EXPECT_NEAR(route->SpeedAt(3.0), 0.7 * 2000.0 * kResolutionM, 1e-9);  // the trough
}

TEST(Route, FloorSmallerThanTheFrameIsRejected) {
  const geometry::ConvexPolygon tiny = geometry::Rectangle(0.0, 0.0, 0.025, 0.025);  // 50×50 px
  const Result<Route> route = Route::Fit(tiny, SmallFootprint(), RouteOptions{}, kResolutionM);
  ASSERT_FALSE(route.ok());
  EXPECT_EQ(route.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(route.status().message().find("too small"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::sim
