// Re-mapping computation on a real floor photo whose floor "changed" in a known place: the patches
// register to the unchanged texture around the change, the new tiles show the changed floor, tiles
// away from the patches are untouched, and the pyramid follows.
#include "mapping/remap.h"

#include <gtest/gtest.h>

#include "mapping/changed_floor_scene.h"
#include "mosaic/pyramid_builder.h"

namespace fleetloc::mapping {
namespace {

using Scene = testing::ChangedFloorScene;
constexpr double kRes = Scene::kRes;

TEST(Remap, ReplaceFoldsTheChangedFloorIntoTheTilesItTouches) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.old_floor, scene.geo);
  const auto fetch = [&](const mosaic::TileKey& k) {
    return source.ReadBlock(k.level, mosaic::TilePixelRect(source.layout(), k));
  };
  const std::vector<Patch> patches = {
      scene.PatchAt({490, 425}, {2.0 * kRes, -1.5 * kRes, 0.3 * M_PI / 180}),
      scene.PatchAt({470, 440}, {-1.0 * kRes, 2.5 * kRes, -0.2 * M_PI / 180})};
  RemapOptions options;
  options.mode = BlendMode::kReplace;
  auto result = ComputeRemap(&source, fetch, patches, options, {}, nullptr);
  ASSERT_TRUE(result.ok()) << result.status().message();
  ASSERT_EQ(result->used, std::vector<bool>({true, true}));
  for (size_t i = 0; i < patches.size(); ++i) {
    const Registration& r = result->registrations[i];
    ASSERT_TRUE(r.registered) << "patch " << i;
    const Eigen::Vector2d truth = scene.geo.PixelToMap(i == 0 ? Eigen::Vector2d(490, 425)
                                                              : Eigen::Vector2d(470, 440));
    EXPECT_LT((Eigen::Vector2d(r.pose.x, r.pose.y) - truth).norm() / kRes, 0.1) << "patch " << i;
    // 0.02° (the tracker's heading target): these patches are exact crops of the floor image,
    // sharper than any camera frame, and the matcher smooths both sides before correlating,
    // which costs an exact crop a little heading (0.017° here at σ 1.5) and a camera frame none (see
    // TrackerOptions::match_smoothing_sigma_px).
    EXPECT_LT(std::abs(r.pose.theta - M_PI / 2), 0.02 * M_PI / 180) << "patch " << i;
  }
  // The new level-0 pixels show the changed floor where the patches cover it.
  cv::Mat assembled = scene.old_floor.clone();
  for (const auto& [key, tile] : result->tiles) {
    if (key.level != 0) continue;
    const cv::Rect r = mosaic::TilePixelRect(source.layout(), key) & cv::Rect(0, 0, 1024, 1024);
    tile(r - r.tl() + (r.tl() - mosaic::TilePixelRect(source.layout(), key).tl())).copyTo(assembled(r));
  }
  cv::Mat diff;
  cv::absdiff(assembled(scene.change), scene.new_floor(scene.change), diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
  cv::absdiff(assembled(scene.change), scene.old_floor(scene.change), diff);
  EXPECT_GT(cv::mean(diff)[0], 15.0);  // the change is real
  // Only the tiles under the patches changed: (1, 1) and its neighbours, not the far corner.
  EXPECT_TRUE(result->tiles.count({0, 1, 1}));
  EXPECT_FALSE(result->tiles.count({0, 3, 3}));
  // Each changed upper tile is the 2×2 mean of the (new) level below.
  for (const auto& [key, tile] : result->tiles) {
    if (key.level == 0) continue;
    const cv::Mat expected = mosaic::DownsampleTile(source.layout(), key, [&](const mosaic::TileKey& c) {
      return result->tiles.count(c) ? result->tiles.at(c) : fetch(c);
    });
    EXPECT_EQ(cv::norm(tile, expected, cv::NORM_INF), 0) << mosaic::ToString(key);
  }
}

TEST(Remap, AnUnregisterablePatchWithAPoorPoseIsRejected) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.old_floor, scene.geo);
  Patch flat;
  flat.image = cv::Mat(240, 320, CV_8UC1, cv::Scalar(128));  // nothing to register on
  flat.pose = {0.25, 0.25, 0.0};
  flat.covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-3).asDiagonal();  // σ = 20 px
  auto result = ComputeRemap(&source, [&](const mosaic::TileKey& k) {
    return source.ReadBlock(k.level, mosaic::TilePixelRect(source.layout(), k));
  }, {flat}, {}, {}, nullptr);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->rejected, 1);
  EXPECT_TRUE(result->tiles.empty());
}

TEST(Remap, CancelStopsBeforeAnythingIsProduced) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.old_floor, scene.geo);
  std::atomic<bool> cancel{true};
  auto result = ComputeRemap(&source, [&](const mosaic::TileKey& k) {
    return source.ReadBlock(k.level, mosaic::TilePixelRect(source.layout(), k));
  }, {scene.PatchAt({490, 425}, {})}, {}, {}, &cancel);
  EXPECT_FALSE(result.ok());
}

}  // namespace
}  // namespace fleetloc::mapping
