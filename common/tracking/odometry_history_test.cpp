// Tests for odometry interpolation, extrapolation and rejection of bad samples.
#include "tracking/odometry_history.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::tracking {
namespace {

TEST(OdometryHistory, InterpolatesPositionAndHeadingAcrossTheWrap) {
  OdometryHistory h;
  ASSERT_TRUE(h.Add({1.0, {0.0, 0.0, M_PI - 0.1}}).ok());
  ASSERT_TRUE(h.Add({2.0, {1.0, 2.0, -M_PI + 0.1}}).ok());
  const auto p = h.At(1.25);
  ASSERT_TRUE(p.ok());
  EXPECT_NEAR(p->x, 0.25, 1e-12);
  EXPECT_NEAR(p->y, 0.5, 1e-12);
  EXPECT_NEAR(p->theta, M_PI - 0.05, 1e-12);  // along the short arc through pi
}

TEST(OdometryHistory, ExtrapolatesAShortWayWithConstantVelocity) {
  OdometryHistory h(10.0, 0.1);
  ASSERT_TRUE(h.Add({0.0, {0.0, 0.0, 0.0}}).ok());
  ASSERT_TRUE(h.Add({0.1, {0.1, 0.0, 0.0}}).ok());
  const auto p = h.At(0.15);
  ASSERT_TRUE(p.ok());
  EXPECT_NEAR(p->x, 0.15, 1e-12);
  EXPECT_FALSE(h.At(0.5).ok());
  EXPECT_FALSE(h.At(-0.1).ok());
}

TEST(OdometryHistory, RejectsNanAndNonMonotonicSamples) {
  OdometryHistory h;
  ASSERT_TRUE(h.Add({1.0, {0, 0, 0}}).ok());
  EXPECT_FALSE(h.Add({2.0, {std::nan(""), 0, 0}}).ok());
  EXPECT_FALSE(h.Add({1.0, {0, 0, 0}}).ok());
  EXPECT_FALSE(h.Add({0.5, {0, 0, 0}}).ok());
  EXPECT_EQ(h.size(), 1u);
}

}  // namespace
}  // namespace fleetloc::tracking
