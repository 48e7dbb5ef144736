// Re-mapping jobs against a stored mosaic: the changed floor reaches the new version's tiles, the
// rest stays byte-identical, patches fold once, and a cancelled job leaves everything as it was.
#include "mosaic/remap_job.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "mapping/changed_floor_scene.h"
#include "mosaic/importer.h"

namespace fleetloc::mosaic {
namespace {

namespace fs = std::filesystem;
using Scene = mapping::testing::ChangedFloorScene;
constexpr double kRes = Scene::kRes;

class RemapJobTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("remap_job_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::string image = (dir_ / "old_floor.png").string();
    ASSERT_TRUE(cv::imwrite(image, scene_.old_floor));
    path_ = (dir_ / "floor.db").string();
    ImportOptions options;
    options.resolution_m = kRes;
    ASSERT_TRUE(ImportImage(image, options, path_).ok());
    store_ = std::move(TileStore::Open(path_, OpenMode::kReadWrite)).value();
    patches_ = std::move(PatchStore::Open(path_)).value();
    int sequence = 0;
    for (const auto& [centre, error] :
         {std::pair{cv::Point(490, 425), geometry::Pose2{2 * kRes, -1.5 * kRes, 0.005}},
          std::pair{cv::Point(470, 440), geometry::Pose2{-kRes, 2.5 * kRes, -0.003}}}) {
      const mapping::Patch p = scene_.PatchAt(centre, error);
      ASSERT_EQ(*patches_->Put({"agv-1", ++sequence, 1.0, p.pose, p.covariance, 0.9, p.image}),
                PutOutcome::kStored);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The region around the change, in map metres.
  MapRect Region() const {
    const Eigen::Vector2d a = scene_.geo.PixelToMap({400, 500}), b = scene_.geo.PixelToMap({600, 350});
    return {a.x(), a.y(), b.x(), b.y()};
  }

  Scene scene_;
  fs::path dir_;
  std::string path_;
  std::unique_ptr<TileStore> store_;
  std::unique_ptr<PatchStore> patches_;
};

TEST_F(RemapJobTest, ReplaceCommitsTheChangedFloorAsTheNextVersion) {
  const auto untouched_before = store_->ReadTileBytes({0, 3, 3});
  std::vector<std::string> phases;
  auto result = RunRemap(*store_, *patches_, {Region(), RemapMode::kReplace},
                         [&](const RemapProgress& p) { phases.push_back(p.phase); });
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->new_version, 2);
  EXPECT_EQ(result->patches_folded, 2);
  EXPECT_EQ(result->patches_rejected, 0);
  EXPECT_EQ(store_->version(), 2);
  EXPECT_NE(std::find(phases.begin(), phases.end(), "commit"), phases.end());
  // Level-0 tile (1, 1) holds most of the change: that part now shows the new floor.
  const cv::Mat tile = *store_->ReadTile({0, 1, 1});
  const cv::Rect part = scene_.change & cv::Rect(256, 256, 256, 256);
  cv::Mat diff;
  cv::absdiff(tile(part - cv::Point(256, 256)), scene_.new_floor(part), diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
  EXPECT_EQ(*store_->ReadTileBytes({0, 3, 3}), *untouched_before);  // far away: unchanged
  // Folded once: a second job finds nothing to do.
  auto again = RunRemap(*store_, *patches_, {Region(), RemapMode::kReplace});
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->new_version, 2);
  EXPECT_TRUE(again->changed_tiles.empty());
}

TEST_F(RemapJobTest, CancelledJobLeavesTheMosaicAndThePatchesAsTheyWere) {
  const auto before = store_->ReadTileBytes({0, 1, 1});
  std::atomic<bool> cancel{true};
  auto result = RunRemap(*store_, *patches_, {Region(), RemapMode::kBlend}, {}, &cancel);
  ASSERT_FALSE(result.ok());
  auto reopened = TileStore::Open(path_, OpenMode::kReadOnly);
  EXPECT_EQ((*reopened)->version(), 1);
  EXPECT_EQ(*(*reopened)->ReadTileBytes({0, 1, 1}), *before);
  EXPECT_EQ(patches_->Unfolded(Region(), 1)->patches.size(), 2u);
  auto rerun = RunRemap(*store_, *patches_, {Region(), RemapMode::kBlend});
  ASSERT_TRUE(rerun.ok()) << rerun.status().message();
  EXPECT_EQ(rerun->new_version, 2);
}

TEST_F(RemapJobTest, BadRegionsAreRejected) {
  const MapRect inverted{0.3, 0.3, 0.2, 0.2}, empty{0.2, 0.2, 0.2, 0.3}, outside{5, 5, 6, 6};
  const MapRect nan{std::nan(""), 0, 1, 1};
  for (const MapRect& r : {inverted, empty, outside, nan}) {
    auto result = RunRemap(*store_, *patches_, {r, RemapMode::kBlend});
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidInput) << result.status().message();
  }
  EXPECT_EQ(store_->version(), 1);
}

}  // namespace
}  // namespace fleetloc::mosaic
