// World file and Nav2 map.yaml: numbers against the geotransform (docs/formats.md) by hand.
#include "mosaic/export_georef.h"

#include <gtest/gtest.h>

#include <sstream>
#include <vector>

namespace fleetloc::mosaic {
namespace {

MosaicLayout Layout() {
  MosaicLayout l;
  l.mosaic_id = "m";
  l.version = 2;
  l.geo = {10.0, 5.0, 0.0005};  // top-left corner of pixel (0, 0) at (10, 5); 0.5 mm per pixel
  l.levels = 4;
  return l;
}

TEST(ExportGeoref, WorldFileNamesFollowTheImage) {
  EXPECT_EQ(WorldFilePath("/a/floor.png"), "/a/floor.pgw");
  EXPECT_EQ(WorldFilePath("floor.JPG"), "floor.jgw");
  EXPECT_EQ(WorldFilePath("floor.tiff"), "floor.tfw");
  EXPECT_EQ(WorldFilePath("floor.pgm"), "floor.pgmw");
}

TEST(ExportGeoref, WorldFilePlacesTheTopLeftPixelCentre) {
  // Level 1 (1 mm per pixel), the rectangle starting at pixel (100, 40).
  std::istringstream text(WorldFileText(Layout(), 1, {100, 40, 50, 20}));
  std::vector<double> v;
  for (double x; text >> x;) v.push_back(x);
  const std::vector<double> want = {0.001, 0, 0, -0.001, 10.1005, 4.9595};
  ASSERT_EQ(v.size(), want.size());
  for (size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(v[i], want[i], 1e-12) << "line " << i + 1;
}

TEST(ExportGeoref, Nav2OriginIsTheBottomLeftCorner) {
  const std::string yaml = Nav2MapYaml(Layout(), 1, {100, 40, 50, 20}, "floor.png");
  EXPECT_NE(yaml.find("image: floor.png\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("resolution: 0.001\n"), std::string::npos) << yaml;
  // x = 10 + 100 mm; y = 5 - (40 + 20) mm.
  double x = 0, y = 0;
  ASSERT_EQ(
      std::sscanf(yaml.substr(yaml.find("origin: [")).c_str(), "origin: [%lf, %lf, 0]", &x, &y), 2)
      << yaml;
  EXPECT_NEAR(x, 10.1, 1e-12);
  EXPECT_NEAR(y, 4.94, 1e-12);
  EXPECT_NE(yaml.find("mode: raw\n"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::mosaic
