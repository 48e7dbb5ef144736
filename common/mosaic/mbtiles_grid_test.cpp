// MBTiles grid math by hand: anchor placement, TMS rows, tile ranges, zoom choice, source level,
// and a rendered tile whose bright block lands where the grid says.
#include "mosaic/mbtiles_grid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::mosaic {
namespace {

constexpr double kWorld = 2.0 * 3.14159265358979323846 * 6378137.0;

MosaicLayout Floor(double res, int w, int h) {
  MosaicLayout l;
  l.width_px = w;
  l.height_px = h;
  l.levels = 4;
  l.geo = {0.0, 0.0, res};
  return l;
}

TEST(MbtilesGrid, TmsRowsCountFromTheBottom) {
  EXPECT_EQ(TmsRow(0, 0), 0);
  EXPECT_EQ(TmsRow(1, 0), 1);
  EXPECT_EQ(TmsRow(1, 1), 0);
  EXPECT_EQ(TmsRow(3, 2), 5);
}

TEST(MbtilesGrid, AnchorScalesMetresByOneOverCosLat) {
  Result<MercatorPlacement> equator = PlaceAt({0.0, 0.0});
  ASSERT_TRUE(equator.ok());
  EXPECT_DOUBLE_EQ(equator->mx0, 0.0);
  EXPECT_NEAR(equator->my0, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(equator->scale, 1.0);
  Result<MercatorPlacement> north = PlaceAt({60.0, 90.0});
  ASSERT_TRUE(north.ok());
  EXPECT_NEAR(north->scale, 2.0, 1e-12);
  EXPECT_NEAR(north->mx0, kWorld / 4.0, 1e-6);
  EXPECT_NEAR(MercYToLat(north->my0), 60.0, 1e-9);
  EXPECT_NEAR(MercXToLon(north->mx0), 90.0, 1e-9);
  EXPECT_FALSE(PlaceAt({86.0, 0.0}).ok());
  EXPECT_FALSE(PlaceAt({0.0, 181.0}).ok());
  EXPECT_FALSE(PlaceAt({std::nan(""), 0.0}).ok());
}

TEST(MbtilesGrid, TilesCoveringKeepsEdgesOnBordersOut) {
  // One tile of zoom 2 exactly: the south-east quarter's top-left tile.
  const double span = kWorld / 4.0;
  const MercTileRange r = TilesCovering({0.0, -span, span, 0.0}, 2);
  EXPECT_EQ(r.col0, 2);
  EXPECT_EQ(r.col1, 2);
  EXPECT_EQ(r.xyz_row0, 2);
  EXPECT_EQ(r.xyz_row1, 2);
  EXPECT_EQ(r.Count(), 1);
  // A little more to the east and south takes the next column and row.
  const MercTileRange wider = TilesCovering({0.0, -span - 1.0, span + 1.0, 0.0}, 2);
  EXPECT_EQ(wider.col1, 3);
  EXPECT_EQ(wider.xyz_row1, 3);
  EXPECT_EQ(wider.Count(), 4);
}

TEST(MbtilesGrid, ZoomsFromTheResolutionAndTheFloorSize) {
  // 1 mm/px at the equator: zoom 28 is 0.58 mm/px (27 would be 1.17); 0.8 m fits one tile at 25.
  const MosaicLayout floor = Floor(0.001, 800, 600);
  const MercatorPlacement equator = *PlaceAt({0.0, 0.0});
  Result<ZoomRange> z = ChooseZooms(floor, equator, kMbtilesMaxZoom);
  ASSERT_TRUE(z.ok());
  EXPECT_EQ(z->max_zoom, 28);
  EXPECT_EQ(z->full_detail_zoom, 28);
  EXPECT_EQ(z->min_zoom, 25);
  EXPECT_LE(MapMetresPerPixel(28, equator), 0.001);
  EXPECT_GT(MapMetresPerPixel(27, equator), 0.001);
  // At 60 degrees a Mercator metre is half a true metre: one zoom less.
  Result<ZoomRange> z60 = ChooseZooms(floor, *PlaceAt({60.0, 0.0}), kMbtilesMaxZoom);
  ASSERT_TRUE(z60.ok());
  EXPECT_EQ(z60->max_zoom, 27);
  EXPECT_EQ(z60->min_zoom, 24);
  // GDAL's cap: only zoom 22, detail lost (full detail still reported).
  Result<ZoomRange> capped = ChooseZooms(floor, equator, kGdalMaxZoom);
  ASSERT_TRUE(capped.ok());
  EXPECT_EQ(capped->max_zoom, 22);
  EXPECT_EQ(capped->min_zoom, 22);
  EXPECT_EQ(capped->full_detail_zoom, 28);
  // Finer than zoom 30 allows is capped too; a cap outside 0..30 is refused.
  Result<ZoomRange> fine = ChooseZooms(Floor(1e-6, 800, 600), equator, kMbtilesMaxZoom);
  ASSERT_TRUE(fine.ok());
  EXPECT_EQ(fine->max_zoom, 30);
  EXPECT_GT(fine->full_detail_zoom, 30);
  EXPECT_FALSE(ChooseZooms(floor, equator, 31).ok());
  EXPECT_FALSE(ChooseZooms(floor, equator, -1).ok());
}

TEST(MbtilesGrid, SourceLevelIsTheCoarsestAtLeastAsFine) {
  const MosaicLayout floor = Floor(0.001, 800, 600);
  EXPECT_EQ(SourceLevel(floor, 0.0005), 0);
  EXPECT_EQ(SourceLevel(floor, 0.0035), 1);
  EXPECT_EQ(SourceLevel(floor, 0.004), 2);
  EXPECT_EQ(SourceLevel(floor, 1.0), 3);
}

TEST(MbtilesGrid, RenderedTileHasTheBrightBlockWhereTheGridSays) {
  // Resolution exactly zoom 20's at the equator: tiles are the image's pixels, shifted by nothing.
  const double res = kWorld / 256.0 / (1 << 20);
  cv::Mat image(512, 512, CV_8U, cv::Scalar(40));
  image(cv::Rect(10, 30, 10, 10)).setTo(255);  // x 10..19, y 30..39 (rows from the top)
  ImageRasterSource source(image, {0.0, 0.0, res});
  Result<MbtilesPlan> plan = PlanMbtiles(source.layout(), {0.0, 0.0}, kGdalMaxZoom);
  ASSERT_TRUE(plan.ok());
  EXPECT_EQ(plan->zooms.max_zoom, 20);
  const MercTileRange& finest = plan->ranges.back();
  EXPECT_EQ(finest.col0, 1 << 19);  // map origin at Mercator (0, 0): the floor is south-east
  EXPECT_EQ(finest.xyz_row0, 1 << 19);
  EXPECT_EQ(finest.Count(), 4);  // 512 px = 2 x 2 tiles
  const cv::Mat tile = RenderTile(source, *plan, 20, 1 << 19, 1 << 19);
  ASSERT_EQ(tile.size(), cv::Size(256, 256));
  EXPECT_EQ(tile.at<uchar>(35, 15), 255);
  EXPECT_EQ(tile.at<uchar>(100, 100), 40);
  EXPECT_EQ(tile.at<uchar>(29, 15), 40);
  // The tile west of the floor is outside it: all 0.
  const cv::Mat west = RenderTile(source, *plan, 20, (1 << 19) - 1, 1 << 19);
  EXPECT_EQ(cv::countNonZero(west), 0);
  // One zoom coarser (from level 1): the block is 5 x 5 pixels at x 5..9, y 15..19.
  const cv::Mat coarse = RenderTile(source, *plan, 19, 1 << 18, 1 << 18);
  EXPECT_EQ(coarse.at<uchar>(17, 7), 255);
  EXPECT_EQ(coarse.at<uchar>(17, 30), 40);
  EXPECT_EQ(coarse.at<uchar>(200, 200), 40);  // level 1 is 256 px: this one tile
  EXPECT_EQ(plan->zooms.min_zoom, 19);
  EXPECT_EQ(plan->total_tiles, 1 + 4);
}

}  // namespace
}  // namespace fleetloc::mosaic
