// fleetctl mosaic export with its georeference, read back by independent readers: GDAL's gdalinfo
// places the exported PNG by its world file exactly where the mosaic's geotransform says
// (docs/formats.md), and the Nav2 map.yaml names the image, its resolution and its bottom-left
// corner.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_runner.h"

namespace fleetloc {
namespace {

TEST(CliMosaicExport, GdalPlacesTheExportedImageWhereTheMosaicSays) {
  testing::ScratchDir dir("cli_mosaic_export");
  cv::Mat floor(600, 800, CV_8U);
  cv::randu(floor, 0, 255);
  const std::string image = (dir.path() / "floor.png").string(),
                    db = (dir.path() / "floor.db").string();
  ASSERT_TRUE(cv::imwrite(image, floor));
  // Top-left corner of the image at map (2, 7), 1 mm per pixel.
  ASSERT_EQ(testing::RunFleetctl("mosaic import " + image +
                                 " --resolution 0.001 --origin 2,7 --out " + db)
                .exit_code,
            0);
  const std::string out = (dir.path() / "export.png").string(),
                    yaml = (dir.path() / "map.yaml").string();
  // Level 1 (2 mm per pixel) over x 2.1..2.5, y 6.7..6.9.
  const testing::CommandResult r =
      testing::RunFleetctl("mosaic export " + db + " --out " + out +
                           " --level 1 --region 2.1,6.7,2.5,6.9 --nav2-yaml " + yaml);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(dir.path() / "export.pgw"));
  const testing::CommandResult info = testing::RunCommand("gdalinfo -json " + testing::Quote(out));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  const nlohmann::json& gt = j.at("geoTransform");  // [x0, px width, 0, y0, 0, -px height]
  EXPECT_NEAR(gt[0].get<double>(), 2.1, 1e-9);
  EXPECT_NEAR(gt[1].get<double>(), 0.002, 1e-12);
  EXPECT_NEAR(gt[3].get<double>(), 6.9, 1e-9);
  EXPECT_NEAR(gt[5].get<double>(), -0.002, 1e-12);
  EXPECT_EQ(j["size"][0], 200);  // 0.4 m at 2 mm
  EXPECT_EQ(j["size"][1], 100);
  const nlohmann::json& corners = j.at("cornerCoordinates");
  EXPECT_NEAR(corners["lowerRight"][0].get<double>(), 2.5, 1e-9);
  EXPECT_NEAR(corners["lowerRight"][1].get<double>(), 6.7, 1e-9);
  const std::string text = testing::ReadWhole(yaml);
  EXPECT_NE(text.find("image: export.png\n"), std::string::npos) << text;
  EXPECT_NE(text.find("resolution: 0.002\n"), std::string::npos) << text;
  double x = 0, y = 0;
  ASSERT_EQ(
      std::sscanf(text.substr(text.find("origin: [")).c_str(), "origin: [%lf, %lf, 0]", &x, &y), 2)
      << text;
  EXPECT_NEAR(x, 2.1, 1e-9);  // the bottom-left corner
  EXPECT_NEAR(y, 6.7, 1e-9);
}

}  // namespace
}  // namespace fleetloc
