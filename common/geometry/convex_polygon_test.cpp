// Tests for convex clipping: rectangle overlaps, the 8-sided case, containment.
#include "geometry/convex_polygon.h"

#include <gtest/gtest.h>

#include <cmath>

#include "geometry/pose2.h"

namespace fleetloc::geometry {
namespace {

TEST(ClipConvex, OverlappingRectanglesGiveTheirIntersection) {
  const ConvexPolygon r = ClipConvex(Rectangle(0, 0, 4, 3), Rectangle(2, 1, 6, 5));
  ASSERT_EQ(r.size(), 4u);
  EXPECT_NEAR(Area(r), 2.0 * 2.0, 1e-12);
}

TEST(ClipConvex, DisjointRectanglesGiveEmpty) {
  EXPECT_TRUE(ClipConvex(Rectangle(0, 0, 1, 1), Rectangle(2, 2, 3, 3)).empty());
}

TEST(ClipConvex, SquareRotatedFortyFiveDegreesOverSquareGivesOctagon) {
  // A square of half-side 1 and the same square turned 45° overlap in a regular octagon.
  ConvexPolygon rotated;
  const Pose2 turn{0, 0, M_PI / 4};
  for (const auto& p : Rectangle(-1, -1, 1, 1)) rotated.push_back(turn * p);
  const ConvexPolygon r = ClipConvex(Rectangle(-1, -1, 1, 1), rotated);
  EXPECT_EQ(r.size(), 8u);
  const double side = 2.0 * (std::sqrt(2.0) - 1.0);  // octagon inscribed in the unit square
  EXPECT_NEAR(Area(r), 2.0 * (1.0 + std::sqrt(2.0)) * side * side, 1e-9);
}

TEST(ClipConvex, ClockwiseInputIsAccepted) {
  ConvexPolygon cw = Rectangle(0, 0, 2, 2);
  std::reverse(cw.begin(), cw.end());
  EXPECT_NEAR(Area(ClipConvex(cw, Rectangle(1, 1, 3, 3))), 1.0, 1e-12);
}

TEST(Contains, InsideOutsideAndBoundary) {
  const ConvexPolygon r = Rectangle(0, 0, 2, 1);
  EXPECT_TRUE(Contains(r, {1, 0.5}));
  EXPECT_TRUE(Contains(r, {2, 1}));
  EXPECT_FALSE(Contains(r, {2.01, 0.5}));
  EXPECT_FALSE(Contains({}, {0, 0}));
}

}  // namespace
TEST(SpanAtY, DiamondIsWidestAtItsMiddleAndMissedOutside) {
  const ConvexPolygon diamond{{0, -2}, {2, 0}, {0, 2}, {-2, 0}};
  const auto [lo, hi] = SpanAtY(diamond, 0.0);
  EXPECT_DOUBLE_EQ(lo, -2.0);
  EXPECT_DOUBLE_EQ(hi, 2.0);
  const auto [lo1, hi1] = SpanAtY(diamond, 1.5);
  EXPECT_DOUBLE_EQ(lo1, -0.5);
  EXPECT_DOUBLE_EQ(hi1, 0.5);
  const auto [lo2, hi2] = SpanAtY(diamond, 3.0);
  EXPECT_GT(lo2, hi2);
}

TEST(SpanAtY, RectangleEdgeLineSpansTheWholeEdge) {
  const auto [lo, hi] = SpanAtY(Rectangle(1, 2, 5, 4), 4.0);
  EXPECT_DOUBLE_EQ(lo, 1.0);
  EXPECT_DOUBLE_EQ(hi, 5.0);
}

}  // namespace fleetloc::geometry
