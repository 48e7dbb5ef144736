// fleetctl mosaic export-mbtiles read back by independent readers: sqlite3 (metadata keys, zoom
// levels, tile counts per zoom, TMS row order: the source image's bright corner mark is found in
// the tile and pixel that Web Mercator arithmetic done here says) and GDAL's gdalinfo (its size and
// geotransform at the finest zoom match the bounds written). Also the refusals (exit 2).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "cli_runner.h"

namespace fleetloc {
namespace {

constexpr double kR = 6378137.0;
constexpr double kPi = 3.14159265358979323846;

// Web Mercator of the anchor used below (lat 45, lon 10) and metres → Mercator metres (1/cos 45).
const double kMx0 = kR * 10.0 * kPi / 180.0;
const double kMy0 = kR * std::log(std::tan(kPi / 4.0 + 45.0 * kPi / 360.0));
const double kScale = 1.0 / std::cos(45.0 * kPi / 180.0);

std::string Sql(const std::string& db, const std::string& query) {
  const testing::CommandResult r = testing::RunCommand(
      "sqlite3 -separator '|' " + testing::Quote(db) + " " + testing::Quote(query));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.out;
}

std::map<std::string, std::string> Rows(const std::string& text) {
  std::map<std::string, std::string> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const std::size_t bar = line.find('|');
    if (bar != std::string::npos) rows[line.substr(0, bar)] = line.substr(bar + 1);
  }
  return rows;
}

struct TilePixel {
  long long col, tms_row;
  int x, y;
};
// The tile (TMS row) and pixel of map point (x, y) at `zoom`, by the MBTiles spec's arithmetic.
TilePixel Locate(double x, double y, int zoom) {
  const double span = 2.0 * kPi * kR / std::ldexp(1.0, zoom);
  const double fx = (kMx0 + x * kScale + kPi * kR) / span,
               fy = (kPi * kR - (kMy0 + y * kScale)) / span;
  const long long col = static_cast<long long>(std::floor(fx)),
                  xyz = static_cast<long long>(std::floor(fy));
  return {col, (1LL << zoom) - 1 - xyz, static_cast<int>((fx - col) * 256),
          static_cast<int>((fy - xyz) * 256)};
}

class CliMbtilesExport : public ::testing::Test {
 protected:
  // An 800 x 600 floor with its top-left corner at map (2, 7), `resolution` m/px.
  void Import(const std::string& resolution) {
    cv::Mat floor(600, 800, CV_8U);
    cv::randu(floor, 20, 100);
    floor(cv::Rect(0, 0, 24, 24)).setTo(255);  // the bright mark at the top-left corner
    image_ = (dir_.path() / "floor.png").string();
    db_ = (dir_.path() / "floor.db").string();
    ASSERT_TRUE(cv::imwrite(image_, floor));
    ASSERT_EQ(testing::RunFleetctl("mosaic import " + image_ + " --resolution " + resolution +
                                   " --origin 2,7 --out " + db_)
                  .exit_code,
              0);
  }
  testing::ScratchDir dir_{"cli_mbtiles_export"};
  std::string image_, db_;
};

TEST_F(CliMbtilesExport, SqliteAndGdalReadTheTilesWhereWebMercatorSays) {
  Import("0.03");  // 3 cm/px: the floor is x 2..26, y -11..7
  const std::string out = (dir_.path() / "floor.mbtiles").string();
  const testing::CommandResult r = testing::RunFleetctl("mosaic export-mbtiles " + db_ + " --out " +
                                                        out + " --anchor-lat 45 --anchor-lon 10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));

  // Metadata: the spec's keys; zooms: at 45 degrees zoom 22 is 26.4 mm/px (21 would be 52.8).
  const std::map<std::string, std::string> meta =
      Rows(Sql(out, "SELECT name, value FROM metadata"));
  for (const char* key : {"name", "format", "bounds", "center", "minzoom", "maxzoom", "type",
                          "version", "description"}) {
    EXPECT_EQ(meta.count(key), 1u) << key;
  }
  EXPECT_EQ(meta.at("format"), "png");
  EXPECT_EQ(meta.at("type"), "baselayer");
  EXPECT_EQ(meta.at("maxzoom"), "22");
  EXPECT_EQ(meta.at("minzoom"), "20");  // 24 m within one tile (27 m at zoom 20, 45 degrees)
  EXPECT_NE(meta.at("description").find("version"), std::string::npos);
  double west = 0, south = 0, east = 0, north = 0;
  ASSERT_EQ(std::sscanf(meta.at("bounds").c_str(), "%lf,%lf,%lf,%lf", &west, &south, &east, &north),
            4);
  EXPECT_NEAR(west, 10.0 + 2.0 * kScale / kR * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(north - south, 18.0 / kR * 180.0 / kPi, 1e-9);  // true metres: 18 m of latitude

  // Tile counts per zoom: the Mercator ranges of the floor's corners.
  const std::map<std::string, std::string> counts =
      Rows(Sql(out, "SELECT zoom_level, COUNT(*) FROM tiles GROUP BY zoom_level"));
  ASSERT_EQ(counts.size(), 3u);
  for (int z = 20; z <= 22; ++z) {
    const TilePixel nw = Locate(2.0, 7.0, z), se = Locate(26.0 - 1e-9, -11.0 + 1e-9, z);
    EXPECT_EQ(counts.at(std::to_string(z)),
              std::to_string((se.col - nw.col + 1) * (nw.tms_row - se.tms_row + 1)))
        << z;
  }

  // TMS rows: the mark's centre (map 2.36, 6.64) is bright in the tile computed here; a point
  // of the random floor is not.
  const TilePixel mark = Locate(2.36, 6.64, 22);
  const std::string png = (dir_.path() / "mark.png").string();
  Sql(out, "SELECT writefile('" + png +
               "', tile_data) FROM tiles WHERE zoom_level = 22 AND tile_column = " +
               std::to_string(mark.col) + " AND tile_row = " + std::to_string(mark.tms_row));
  const cv::Mat tile = cv::imread(png, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(tile.empty()) << "no tile at column " << mark.col << ", TMS row " << mark.tms_row;
  ASSERT_EQ(tile.size(), cv::Size(256, 256));
  EXPECT_GT(tile.at<uchar>(mark.y, mark.x), 200);
  const TilePixel plain = Locate(14.0, -2.0, 22);
  Sql(out, "SELECT writefile('" + png +
               "', tile_data) FROM tiles WHERE zoom_level = 22 AND tile_column = " +
               std::to_string(plain.col) + " AND tile_row = " + std::to_string(plain.tms_row));
  const cv::Mat floor_tile = cv::imread(png, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(floor_tile.empty());
  EXPECT_LT(floor_tile.at<uchar>(plain.y, plain.x), 120);
  EXPECT_GT(floor_tile.at<uchar>(plain.y, plain.x), 0);

  // GDAL opens the finest zoom over the bounds written: Web Mercator pixel size of zoom 22, the
  // floor's corners within a pixel.
  const testing::CommandResult info = testing::RunCommand("gdalinfo -json " + testing::Quote(out));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const nlohmann::json j = nlohmann::json::parse(info.out);
  const nlohmann::json& gt = j.at("geoTransform");
  const double px = 2.0 * kPi * kR / std::ldexp(1.0, 22) / 256.0;
  EXPECT_NEAR(gt[1].get<double>(), px, 1e-9);
  EXPECT_NEAR(gt[5].get<double>(), -px, 1e-9);
  EXPECT_NEAR(gt[0].get<double>(), kMx0 + 2.0 * kScale, px);
  EXPECT_NEAR(gt[3].get<double>(), kMy0 + 7.0 * kScale, px);
  EXPECT_NEAR(j["size"][0].get<double>() * px, 24.0 * kScale, 2 * px);
  EXPECT_NEAR(j["size"][1].get<double>() * px, 18.0 * kScale, 2 * px);
}

TEST_F(CliMbtilesExport, AFinerMosaicIsCappedAtGdalsZoomAndSaysSo) {
  Import("0.001");  // 1 mm/px needs zoom 27 at 45 degrees; GDAL opens up to 22
  const std::string out = (dir_.path() / "capped.mbtiles").string();
  const testing::CommandResult r = testing::RunFleetctl("mosaic export-mbtiles " + db_ + " --out " +
                                                        out + " --anchor-lat 45 --anchor-lon 10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("full detail needs zoom 27; written up to zoom 22"), std::string::npos)
      << r.err;
  const std::map<std::string, std::string> meta =
      Rows(Sql(out, "SELECT name, value FROM metadata"));
  EXPECT_EQ(meta.at("maxzoom"), "22");
  EXPECT_EQ(meta.at("minzoom"), "22");
  EXPECT_EQ(Sql(out, "SELECT DISTINCT zoom_level FROM tiles"), "22\n");
  EXPECT_EQ(testing::RunCommand("gdalinfo -json " + testing::Quote(out)).exit_code, 0);
}

TEST_F(CliMbtilesExport, TooManyTilesABadAnchorOrZoomIsRefused) {
  Import("0.03");
  const std::string out = (dir_.path() / "refused.mbtiles").string();
  EXPECT_TRUE(testing::IsBadInput(
      testing::RunFleetctl("mosaic export-mbtiles " + db_ + " --out " + out + " --max-tiles 5"),
      {"tiles", "more than --max-tiles 5"}));
  EXPECT_TRUE(testing::IsBadInput(
      testing::RunFleetctl("mosaic export-mbtiles " + db_ + " --out " + out + " --anchor-lat 89"),
      {"anchor", "Web Mercator"}));
  EXPECT_TRUE(testing::IsBadInput(
      testing::RunFleetctl("mosaic export-mbtiles " + db_ + " --out " + out + " --max-zoom 31"),
      {"--max-zoom 31", "0..30"}));
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
}

}  // namespace
}  // namespace fleetloc
