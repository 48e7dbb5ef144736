// Tests for the mosaic geotransform (docs/formats.md).
#include "geometry/geotransform.h"

#include <gtest/gtest.h>

namespace fleetloc::geometry {
namespace {

TEST(Geotransform, PixelCornerAndCentreFollowGdalConvention) {
  const Geotransform g{10.0, 5.0, 0.0005};
  const Eigen::Vector2d corner = g.PixelToMap({0, 0});
  EXPECT_DOUBLE_EQ(corner.x(), 10.0);
  EXPECT_DOUBLE_EQ(corner.y(), 5.0);
  // Centre of pixel (i=2, j=3) is (2.5, 3.5): x grows right, y decreases down the image.
  const Eigen::Vector2d centre = g.PixelToMap({2.5, 3.5});
  EXPECT_NEAR(centre.x(), 10.0 + 2.5 * 0.0005, 1e-12);
  EXPECT_NEAR(centre.y(), 5.0 - 3.5 * 0.0005, 1e-12);
}

TEST(Geotransform, RoundTripsAndScalesWithLevel) {
  const Geotransform g{-1.0, 2.0, 0.001};
  const Eigen::Vector2d uv(123.25, 456.75);
  EXPECT_TRUE(g.MapToPixel(g.PixelToMap(uv)).isApprox(uv, 1e-12));
  const Geotransform l2 = g.AtLevel(2);
  EXPECT_DOUBLE_EQ(l2.resolution, 0.004);
  EXPECT_TRUE(l2.PixelToMap(uv / 4.0).isApprox(g.PixelToMap(uv), 1e-12));
}

}  // namespace
}  // namespace fleetloc::geometry
