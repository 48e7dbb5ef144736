// Tests for level export: whole levels and map regions come back pixel-exact; bad levels and
// regions are rejected.
#include "mosaic/exporter.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "mosaic/importer.h"
#include "mosaic/mosaic_view.h"
#include "mosaic/test_util.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::ScratchDir;
using testing::SourcePath;

constexpr char kPhoto[] = "tests/data/grass.png";  // 512 x 512
constexpr double kResolution = 0.001;

// An imported real photo (origin (0, 0.512)) and a view over it.
class ExporterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ImportOptions options;
    options.resolution_m = kResolution;
    ASSERT_TRUE(ImportImage(SourcePath(kPhoto), options, dir_.File("m.db")).ok());
    std::shared_ptr<TileStore> store =
        std::move(TileStore::Open(dir_.File("m.db"), OpenMode::kReadOnly)).value();
    view_ = std::make_unique<MosaicView>(store->layout(), MakeTileLoader(store),
                                         std::make_shared<TileCache>(4 << 20));
    gray_ = LoadGray(SourcePath(kPhoto));
  }
  cv::Mat ReadBack(const std::string& path) { return cv::imread(path, cv::IMREAD_UNCHANGED); }

  ScratchDir dir_;
  std::unique_ptr<MosaicView> view_;
  cv::Mat gray_;
};

TEST_F(ExporterTest, WholeLevelsRoundTrip) {
  Result<cv::Rect> rect = ExportImage(*view_, 0, std::nullopt, dir_.File("l0.png"));
  ASSERT_TRUE(rect.ok()) << rect.status().message();
  EXPECT_EQ(*rect, cv::Rect(0, 0, 512, 512));
  EXPECT_EQ(MaxAbsDiff(ReadBack(dir_.File("l0.png")), gray_), 0);
  ASSERT_TRUE(ExportImage(*view_, 1, std::nullopt, dir_.File("l1.bmp")).ok());  // via imwrite
  cv::Mat half;
  cv::resize(gray_, half, {}, 0.5, 0.5, cv::INTER_AREA);
  EXPECT_LE(MaxAbsDiff(ReadBack(dir_.File("l1.bmp")), half), 1);
}

TEST_F(ExporterTest, MapRegionSelectsPixelsPerGeotransform) {
  // x in [0.1, 0.25] m → u in [100, 250); y in [0.3, 0.412] m → v in [100, 212).
  const MapRegion region{0.25, 0.3, 0.1, 0.412};  // corners in any order
  Result<cv::Rect> rect = ExportImage(*view_, 0, region, dir_.File("r.png"));
  ASSERT_TRUE(rect.ok()) << rect.status().message();
  EXPECT_EQ(*rect, cv::Rect(100, 100, 150, 112));
  EXPECT_EQ(MaxAbsDiff(ReadBack(dir_.File("r.png")), gray_(*rect)), 0);
  // Partly outside (x < 0): the outside is black.
  ASSERT_TRUE(ExportImage(*view_, 1, MapRegion{-0.02, 0.5, 0.02, 0.46}, dir_.File("o.png")).ok());
  const cv::Mat out = ReadBack(dir_.File("o.png"));
  ASSERT_EQ(out.size(), cv::Size(20, 20));  // level 1: 2 mm pixels
  EXPECT_EQ(cv::countNonZero(out(cv::Rect(0, 0, 10, 20))), 0);
  EXPECT_GT(cv::countNonZero(out(cv::Rect(10, 0, 10, 20))), 150);
}

TEST_F(ExporterTest, BadLevelRegionOrFormatIsRejected) {
  EXPECT_EQ(ExportImage(*view_, 2, std::nullopt, dir_.File("a.png")).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(ExportImage(*view_, -1, std::nullopt, dir_.File("a.png")).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(ExportImage(*view_, 0, MapRegion{5, 5, 6, 6}, dir_.File("a.png")).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(
      ExportImage(*view_, 0, MapRegion{0.1, 0.1, 0.1, 0.2}, dir_.File("a.png")).status().code(),
      StatusCode::kInvalidInput);
  EXPECT_EQ(ExportImage(*view_, 0, MapRegion{0, 0, NAN, 1}, dir_.File("a.png")).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(ExportImage(*view_, 0, std::nullopt, dir_.File("a.xyz")).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(ExportImage(*view_, 0, std::nullopt, dir_.File("no/dir/a.png")).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_FALSE(std::filesystem::exists(dir_.File("a.png")));
}

}  // namespace
}  // namespace fleetloc::mosaic
