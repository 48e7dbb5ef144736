// Forward camera model: floor ↔ pixel round trips, the principal ray, the horizon, the nadir
// vanishing point and invalid parameters.
#include "mapmatch/forward_camera.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace fleetloc::mapmatch {
namespace {

// A 640×480 camera 1 m above the floor, pitched 0.25 rad down, with barrel distortion.
ForwardCameraParams TypicalParams() {
  ForwardCameraParams p;
  p.K = {520, 0, 318.5, 0, 521, 243.25, 0, 0, 1};
  p.dist = {-0.12, 0.03, 4e-4, -3e-4, -0.004};
  p.mount = {.x_m = 0.45, .y_m = -0.05, .height_m = 1.0, .yaw_rad = 0.0, .pitch_rad = 0.25};
  return p;
}

bool InsideImage(const ForwardCameraParams& p, const Eigen::Vector2d& px) {
  return px.x() >= 0 && px.y() >= 0 && px.x() <= p.width_px && px.y() <= p.height_px;
}

// Whether the camera sees a point inside its image without distortion (where the lens model is
// used; the test's points further out may fold back into the image through the polynomial).
bool InsideIdealImage(const ForwardCamera& camera, const Eigen::Vector3d& point) {
  const Eigen::Vector3d p = camera.rotation().transpose() * (point - camera.center());
  return p.z() > 0 &&
         InsideImage(camera.params(), camera.NormalizedToIdealPixel(p.head<2>() / p.z()));
}

// Projects a grid of floor points and maps each visible one back to the floor.
void ExpectFloorRoundTrip(const ForwardCameraParams& params) {
  const ForwardCamera camera = ForwardCamera::Create(params).value();
  int visible = 0;
  for (double x = 1.0; x <= 10.0; x += 0.25) {
    for (double y = -4.0; y <= 4.0; y += 0.25) {
      Result<Eigen::Vector2d> pixel = camera.Project({x, y, 0.0});
      if (!InsideIdealImage(camera, {x, y, 0.0})) continue;
      ASSERT_TRUE(pixel.ok()) << pixel.status().message();
      ++visible;
      Result<Eigen::Vector2d> floor = camera.PixelToFloor(*pixel);
      ASSERT_TRUE(floor.ok()) << floor.status().message();
      EXPECT_NEAR(floor->x(), x, 1e-9) << "at " << x << ", " << y;
      EXPECT_NEAR(floor->y(), y, 1e-9) << "at " << x << ", " << y;
    }
  }
  EXPECT_GT(visible, 200);
}

TEST(ForwardCamera, FloorPointRoundTripIsExactToANanometre) {
  ExpectFloorRoundTrip(TypicalParams());
}

TEST(ForwardCamera, RoundTripWithYawRollAndStrongDistortion) {
  ForwardCameraParams params = TypicalParams();
  params.dist = {-0.3, 0.12, -1e-3, 2e-3, -0.02};
  params.mount.yaw_rad = 0.3;
  params.mount.roll_rad = -0.05;
  params.mount.pitch_rad = 0.4;
  ExpectFloorRoundTrip(params);
}

TEST(ForwardCamera, ThePrincipalRayMeetsTheFloorStraightAheadAtHeightOverTanPitch) {
  const ForwardCameraParams params = TypicalParams();
  const ForwardCamera camera = ForwardCamera::Create(params).value();
  const double ahead = params.mount.height_m / std::tan(params.mount.pitch_rad);
  const Eigen::Vector2d floor(params.mount.x_m + ahead, params.mount.y_m);
  const Eigen::Vector2d pixel = camera.Project({floor.x(), floor.y(), 0.0}).value();
  EXPECT_NEAR(pixel.x(), params.K[2], 1e-9);
  EXPECT_NEAR(pixel.y(), params.K[5], 1e-9);
  EXPECT_NEAR((camera.IdealPixelToFloor({params.K[2], params.K[5]}).value() - floor).norm(), 0,
              1e-12);
}

TEST(ForwardCamera, PixelsAboveTheHorizonFailClearly) {
  const ForwardCameraParams params = TypicalParams();
  const ForwardCamera camera = ForwardCamera::Create(params).value();
  // The horizon row of the ideal image, straight ahead.
  const double horizon_v = params.K[5] - params.K[4] * std::tan(params.mount.pitch_rad);
  Result<Eigen::Vector2d> above = camera.IdealPixelToFloor({params.K[2], horizon_v - 1.0});
  ASSERT_FALSE(above.ok());
  EXPECT_EQ(above.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(above.status().message().find("above the horizon"), std::string::npos)
      << above.status().message();
  EXPECT_FALSE(camera.PixelToFloor({320.0, 0.0}).ok()) << "the top row is above the horizon";
  Result<Eigen::Vector2d> below = camera.IdealPixelToFloor({params.K[2], horizon_v + 1.0});
  ASSERT_TRUE(below.ok());
  EXPECT_GT(below->x(), 100.0) << "one pixel below the horizon is far away";
}

TEST(ForwardCamera, PointsBehindTheCameraDoNotProject) {
  const ForwardCamera camera = ForwardCamera::Create(TypicalParams()).value();
  Result<Eigen::Vector2d> pixel = camera.Project({-2.0, 0.0, 0.0});
  ASSERT_FALSE(pixel.ok());
  EXPECT_NE(pixel.status().message().find("not in front"), std::string::npos);
}

// The ideal-image line through a vertical edge's foot and top passes through the vanishing point.
TEST(ForwardCamera, VerticalLinesMeetAtTheNadirVanishingPoint) {
  ForwardCameraParams params = TypicalParams();
  params.dist = {};
  for (double pitch : {0.0, 0.25}) {
    params.mount.pitch_rad = pitch;
    const ForwardCamera camera = ForwardCamera::Create(params).value();
    const Eigen::Vector3d vp = camera.NadirVanishingPoint();
    for (const Eigen::Vector2d& foot : {Eigen::Vector2d(3, 1), Eigen::Vector2d(5, -1.5)}) {
      const Eigen::Vector2d a = camera.Project({foot.x(), foot.y(), 0.0}).value();
      const Eigen::Vector2d b = camera.Project({foot.x(), foot.y(), 1.5}).value();
      const Eigen::Vector3d line =
          Eigen::Vector3d(a.x(), a.y(), 1).cross(Eigen::Vector3d(b.x(), b.y(), 1));
      EXPECT_NEAR(line.dot(vp) / (line.head<2>().norm() * vp.norm()), 0.0, 1e-12) << pitch;
    }
    if (pitch == 0.0) {
      EXPECT_EQ(vp.z(), 0.0) << "a level camera sees verticals parallel";
    } else {
      EXPECT_GT(vp.y() / vp.z(), params.height_px) << "pitched down: below the image";
    }
  }
}

TEST(ForwardCamera, InvalidParametersNameTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    void (*apply)(ForwardCameraParams*, double);
    const char* field;
  };
  const Case cases[] = {
      {[](ForwardCameraParams* p, double v) { p->K[2] = v; }, "'K'"},
      {[](ForwardCameraParams* p, double) { p->K[0] = -1; }, "'K'"},
      {[](ForwardCameraParams* p, double v) { p->dist[1] = v; }, "'dist'"},
      {[](ForwardCameraParams* p, double) { p->width_px = 0; }, "'width'"},
      {[](ForwardCameraParams* p, double) { p->mount.height_m = 0; }, "'mount.height'"},
      {[](ForwardCameraParams* p, double v) { p->mount.pitch_rad = v; }, "'mount.pitch'"},
      {[](ForwardCameraParams* p, double) { p->mount.pitch_rad = 1.6; }, "'mount.pitch'"},
      {[](ForwardCameraParams* p, double v) { p->mount.yaw_rad = v; }, "'mount.yaw'"},
  };
  for (const Case& c : cases) {
    ForwardCameraParams params = TypicalParams();
    c.apply(&params, nan);
    Result<ForwardCamera> camera = ForwardCamera::Create(params);
    ASSERT_FALSE(camera.ok()) << c.field;
    EXPECT_EQ(camera.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(camera.status().message().find(std::string("field ") + c.field), std::string::npos)
        << camera.status().message();
  }
}

}  // namespace
}  // namespace fleetloc::mapmatch
