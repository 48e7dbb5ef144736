// Tests of the dense alignment's view sampling (point_views.h): the view and gradient of a known
// block, what lies outside it, and the vector loop's floats against the scalar loop's.
#include "tracking/point_views.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace fleetloc::tracking {
namespace {

// A level turned by `angle` and shifted by (tx, ty) into the mosaic, gradients scaled by `scale`.
PointWarp TurnedWarp(float angle, float tx, float ty, float scale) {
  const float c = std::cos(angle), s = std::sin(angle);
  return PointWarp{{{c, -s}, {s, c}}, {tx, ty}, {{c, s}, {-s, c}}, scale};
}

// `n` pixels scattered over [lo, hi)² of the level, in a fixed pseudo-random order.
PointSet ScatteredPoints(int n, float lo, float hi, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> at(lo, hi);
  PointSet points;
  for (int i = 0; i < n; ++i) {
    points.u.push_back(at(random));
    points.v.push_back(at(random));
    points.value.push_back(0.0f);
    points.du0.push_back(0.0f);
    points.dv0.push_back(0.0f);
  }
  points.block_start.back() = n;
  return points;
}

// Block texels (CV_32FC4) of the plane a·x + b·y + c over block pixels, gradient (a, b).
cv::Mat PlaneTexels(cv::Size size, float a, float b, float c) {
  cv::Mat texels(size, CV_32FC4);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) texels.at<cv::Vec4f>(y, x) = {a * x + b * y + c, a, b, 0};
  }
  return texels;
}

TEST(SamplePointViews, GivesThePlanesValueAndTurnedGradientAndNothingOutside) {
  const cv::Mat texels = PlaneTexels({120, 100}, 0.03f, -0.02f, 0.5f);
  const TexelBlock block{&texels, {40, 30}, {150, 140}};  // the level ends inside the block
  const PointWarp warp = TurnedWarp(0.2f, 60.0f, 40.0f, 0.5f);
  PointSet points = ScatteredPoints(1001, -20.0f, 160.0f, 7);
  points.u[5] = std::numeric_limits<float>::quiet_NaN();
  PointViews views;
  SamplePointViews(warp, block, points, &views);
  ASSERT_EQ(views.seen.size(), points.size());
  int seen = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const float u = points.u[i], v = points.v[i];
    const float mx = warp.linear[0][0] * u + warp.linear[0][1] * v + warp.offset[0];
    const float my = warp.linear[1][0] * u + warp.linear[1][1] * v + warp.offset[1];
    const float bx = mx - 0.5f - 40.0f, by = my - 0.5f - 30.0f;
    const bool inside = mx >= 0.5f && my >= 0.5f && mx <= 149.5f && my <= 139.5f && bx >= 0 &&
                        by >= 0 && bx < 119.0f && by < 99.0f;
    if (!inside) {
      EXPECT_EQ(views.seen[i], 0.0f) << i;
      EXPECT_EQ(views.value[i] + views.gx[i] + views.gy[i], 0.0f) << i;
      continue;
    }
    ++seen;
    EXPECT_EQ(views.seen[i], 1.0f) << i;
    EXPECT_NEAR(views.value[i], 0.03f * bx - 0.02f * by + 0.5f, 1e-4) << i;
    EXPECT_NEAR(views.gx[i], (warp.to_frame[0][0] * 0.03f - warp.to_frame[0][1] * 0.02f) * 0.5f,
                1e-6);
    EXPECT_NEAR(views.gy[i], (warp.to_frame[1][0] * 0.03f - warp.to_frame[1][1] * 0.02f) * 0.5f,
                1e-6);
  }
  EXPECT_GT(seen, 300);
  EXPECT_LT(seen, 900);  // both sides of every bound are exercised
}

TEST(SamplePointViews, TheVectorLoopGivesTheScalarLoopsFloats) {
  cv::Mat texels(90, 130, CV_32FC4);
  cv::randu(texels, cv::Scalar::all(-2.0), cv::Scalar::all(2.0));
  const TexelBlock block{&texels, {-3, 5}, {200, 200}};
  for (const float angle : {0.0f, 0.3f, -1.1f}) {
    const PointWarp warp = TurnedWarp(angle, 30.0f, 45.0f, 0.25f);
    PointSet points = ScatteredPoints(1003, -40.0f, 120.0f, 11);  // not a multiple of 8
    points.v[17] = std::numeric_limits<float>::infinity();
    PointViews fastest, scalar;
    SamplePointViews(warp, block, points, &fastest, SamplingPath::kFastest);
    SamplePointViews(warp, block, points, &scalar, SamplingPath::kScalar);
    EXPECT_EQ(fastest.value, scalar.value) << angle;
    EXPECT_EQ(fastest.gx, scalar.gx) << angle;
    EXPECT_EQ(fastest.gy, scalar.gy) << angle;
    EXPECT_EQ(fastest.seen, scalar.seen) << angle;
  }
}

}  // namespace
}  // namespace fleetloc::tracking
