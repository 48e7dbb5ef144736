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

TEST(OdometryHistory, GapAroundIsTheSpacingOfTheSamplesAroundATime) {
  OdometryHistory h(10.0, 0.0);
  for (double t : {1.0, 1.01, 1.02, 2.5, 2.51}) ASSERT_TRUE(h.Add({t, {t, 0.0, 0.0}}).ok());
  EXPECT_NEAR(h.GapAround(1.005), 0.01, 1e-12);
  EXPECT_NEAR(h.GapAround(2.0), 1.48, 1e-12);  // odometry stopped for 1.48 s
  EXPECT_EQ(h.GapAround(0.5), 0.0);            // before the history
  EXPECT_EQ(h.GapAround(2.6), 0.0);            // past the newest sample
}

}  // namespace
}  // namespace fleetloc::tracking
