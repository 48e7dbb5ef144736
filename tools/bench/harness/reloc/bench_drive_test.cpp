// The relocalization bench's vehicle on a floor of 1024 px (0.5 mm/px) with a 320×240 camera:
// straight where the floor allows, one direction a trial, to and fro where it is too short,
// every frame on the floor, and no frame a copy of the first one's place.
#include "harness/reloc/bench_drive.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::bench {
namespace {

constexpr double kResolutionM = 0.0005;

struct Floor {
  mosaic::MosaicLayout layout;
  geometry::CameraModel camera;
  explicit Floor(int side_px) {
    layout.width_px = layout.height_px = side_px;
    layout.geo = {0.0, side_px * kResolutionM, kResolutionM};
    camera.width_px = 320;
    camera.height_px = 240;
    camera.cx_px = 160;
    camera.cy_px = 120;
    camera.resolution_m = kResolutionM;
    camera.mount = {0.40, 0.0, 0.0};
  }
  // base_link whose camera centre is at level-0 pixel (u, v), heading along map x.
  geometry::Pose2 BaseAt(double u, double v) const {
    const Eigen::Vector2d xy = layout.geo.PixelToMap({u, v});
    return geometry::Pose2{xy.x(), xy.y(), 0.0} * camera.mount.Inverse();
  }
};

// Distance driven along the heading from `start` to `pose` (signed), metres.
double Along(const geometry::Pose2& start, const geometry::Pose2& pose) {
  return (start.Inverse() * pose).x;
}

TEST(BenchDrive, AFloorLongEnoughIsDrivenStraightAhead) {
  const Floor f(1024);
  const geometry::Pose2 start = f.BaseAt(300, 512);
  for (int k = 0; k < 4; ++k) {
    const geometry::Pose2 p = PoseAtFrame(f.layout, f.camera, start, k, 0.05);
    EXPECT_NEAR(Along(start, p), 0.05 * k, 1e-12);
    EXPECT_NEAR((start.Inverse() * p).y, 0.0, 1e-12);
  }
}

TEST(BenchDrive, WhereAStepAheadLeavesTheFloorEveryFrameGoesBack) {
  const Floor f(1024);
  const geometry::Pose2 start = f.BaseAt(800, 512);  // 24 px of room ahead, 600 behind
  for (int k = 1; k < 4; ++k)
    EXPECT_NEAR(Along(start, PoseAtFrame(f.layout, f.camera, start, k, 0.05)), -0.05 * k, 1e-12);
}

// `all` at 320×240: 0.2 m (400 px) a frame, 624 px of room along the heading. Until session 46
// the third frame stood at the first one's place.
TEST(BenchDrive, AFloorTooShortIsDrivenToAndFroOverDifferentPlaces) {
  const Floor f(1024);
  const double step_m = 0.2;
  for (const double u : {250.0, 512.0, 700.0}) {
    const geometry::Pose2 start = f.BaseAt(u, 512);
    double previous = 0.0;
    for (int k = 1; k < 8; ++k) {
      const geometry::Pose2 p = PoseAtFrame(f.layout, f.camera, start, k, step_m);
      ASSERT_TRUE(FrameFits(f.layout, f.camera, p)) << u << " " << k;
      const double at = Along(start, p);
      EXPECT_NEAR((start.Inverse() * p).y, 0.0, 1e-9);
      // A step or less from the last frame (less where it reversed; the floor's ends are found to
      // a few nanometres), never standing.
      EXPECT_LE(std::abs(at - previous), step_m + 1e-6) << u << " " << k;
      EXPECT_GT(std::abs(at - previous), 0.01) << u << " " << k;
      previous = at;
    }
    // The first three frames see three places, none a copy of another (a frame that reverses
    // near the floor's end comes back close to the last one: 52 px from it at u = 250).
    const double a1 = Along(start, PoseAtFrame(f.layout, f.camera, start, 1, step_m));
    const double a2 = Along(start, PoseAtFrame(f.layout, f.camera, start, 2, step_m));
    EXPECT_GT(std::abs(a1), 0.05) << u;
    EXPECT_GT(std::abs(a2), 0.05) << u;
    EXPECT_GT(std::abs(a2 - a1), 0.02) << u;
  }
}

TEST(BenchDrive, AFloorNoLongerThanTheFrameLeavesTheVehicleStanding) {
  const Floor f(401);  // the frame's diagonal is 400 px: no room to move
  const geometry::Pose2 start = f.BaseAt(200.5, 200.5);
  ASSERT_TRUE(FrameFits(f.layout, f.camera, start));
  const geometry::Pose2 p = PoseAtFrame(f.layout, f.camera, start, 2, 0.2);
  EXPECT_NEAR(Along(start, p), 0.0, 1e-3);
}

}  // namespace
}  // namespace fleetloc::bench
