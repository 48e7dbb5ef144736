// Re-mapping computation on a real floor photo whose floor "changed" in a known place: the patches
// register to the unchanged texture around the change, the new tiles show the changed floor, tiles
// away from the patches are untouched, and the pyramid follows; a forged vehicle's patches change
// nothing; with corroboration a change waits for a second vehicle.
#include "mapping/remap.h"

#include <gtest/gtest.h>

#include "mapping/forged_patches.h"
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
  VectorPatchSource patches(
      {scene.PatchAt({490, 425}, {2.0 * kRes, -1.5 * kRes, 0.3 * M_PI / 180}),
       scene.PatchAt({470, 440}, {-1.0 * kRes, 2.5 * kRes, -0.2 * M_PI / 180})});
  RemapOptions options;
  options.mode = BlendMode::kReplace;
  auto result = ComputeRemap(&source, fetch, patches, options, {}, nullptr);
  ASSERT_TRUE(result.ok()) << result.status().message();
  ASSERT_EQ(result->Count(PatchFate::kFolded), 2);
  for (size_t i = 0; i < 2; ++i) {
    const Admission& r = result->outcomes[i].admission;
    ASSERT_TRUE(r.admitted()) << "patch " << i << ": " << r.reason;
    const Eigen::Vector2d truth =
        scene.geo.PixelToMap(i == 0 ? Eigen::Vector2d(490, 425) : Eigen::Vector2d(470, 440));
    EXPECT_LT((Eigen::Vector2d(r.pose.x, r.pose.y) - truth).norm() / kRes, 0.1) << "patch " << i;
    // 0.02° (the tracker's heading target): these patches are exact crops of the floor image,
    // sharper than any camera frame, and the matcher smooths both sides before correlating,
    // which costs an exact crop a little heading (0.017° here at σ 1.5) and a camera frame none
    // (see TrackerOptions::match_smoothing_sigma_px).
    EXPECT_LT(std::abs(r.pose.theta - M_PI / 2), 0.02 * M_PI / 180) << "patch " << i;
  }
  // The new level-0 pixels show the changed floor where the patches cover it.
  cv::Mat assembled = scene.old_floor.clone();
  for (const auto& [key, tile] : result->tiles) {
    if (key.level != 0) continue;
    const cv::Rect r = mosaic::TilePixelRect(source.layout(), key) & cv::Rect(0, 0, 1024, 1024);
    tile(r - r.tl() + (r.tl() - mosaic::TilePixelRect(source.layout(), key).tl()))
        .copyTo(assembled(r));
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
    const cv::Mat expected =
        mosaic::DownsampleTile(source.layout(), key, [&](const mosaic::TileKey& c) {
          return result->tiles.count(c) ? result->tiles.at(c) : fetch(c);
        });
    EXPECT_EQ(cv::norm(tile, expected, cv::NORM_INF), 0) << mosaic::ToString(key);
  }
}

// The current mosaic's tiles as ComputeRemap reads them.
TileFetch FetchFrom(mosaic::ImageRasterSource& source) {
  return [&source](const mosaic::TileKey& k) {
    return source.ReadBlock(k.level, mosaic::TilePixelRect(source.layout(), k));
  };
}

TEST(Remap, AForgedVehicleChangesNoTileInEitherMode) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.old_floor, scene.geo);
  std::vector<Patch> forged;
  for (cv::Point centre : {cv::Point(490, 425), cv::Point(300, 300), cv::Point(700, 600)}) {
    for (testing::ForgedPatch& f : testing::ForgedPatches(scene, centre)) forged.push_back(f.patch);
  }
  for (BlendMode mode : {BlendMode::kBlend, BlendMode::kReplace}) {
    VectorPatchSource patches(forged);
    RemapOptions options;
    options.mode = mode;
    auto result = ComputeRemap(&source, FetchFrom(source), patches, options, {}, nullptr);
    ASSERT_TRUE(result.ok()) << result.status().message();
    EXPECT_EQ(result->Count(PatchFate::kRefused), static_cast<int>(forged.size()));
    EXPECT_TRUE(result->tiles.empty());  // not one pixel of the mosaic changes
    for (const PatchOutcome& o : result->outcomes) EXPECT_FALSE(o.reason.empty());
  }
}

TEST(Remap, WithCorroborationAOneVehicleChangeIsHeldUntilASecondVehicleSeesIt) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.old_floor, scene.geo);
  auto from = [&](cv::Point centre, const char* vehicle) {
    Patch p = scene.PatchAt(centre, {});
    p.vehicle_id = vehicle;
    return p;
  };
  RemapOptions options;
  options.mode = BlendMode::kReplace;
  options.corroboration.min_vehicles = 2;
  VectorPatchSource alone({from({490, 425}, "agv-1"), from({470, 440}, "agv-1"),
                           testing::SplicedPatch(scene, {700, 600}, "forger")});
  auto held = ComputeRemap(&source, FetchFrom(source), alone, options, {}, nullptr);
  ASSERT_TRUE(held.ok());
  EXPECT_EQ(held->Count(PatchFate::kHeld), 3);
  EXPECT_TRUE(held->tiles.empty());
  VectorPatchSource seen_twice({from({490, 425}, "agv-1"), from({470, 440}, "agv-2")});
  auto folded = ComputeRemap(&source, FetchFrom(source), seen_twice, options, {}, nullptr);
  ASSERT_TRUE(folded.ok());
  EXPECT_EQ(folded->Count(PatchFate::kFolded), 2);
  EXPECT_TRUE(folded->tiles.count({0, 1, 1}));
}

TEST(Remap, CancelStopsBeforeAnythingIsProduced) {
  Scene scene;
  mosaic::ImageRasterSource source(scene.old_floor, scene.geo);
  std::atomic<bool> cancel{true};
  VectorPatchSource patches({scene.PatchAt({490, 425}, {})});
  auto result = ComputeRemap(&source, FetchFrom(source), patches, {}, {}, &cancel);
  EXPECT_FALSE(result.ok());
}

}  // namespace
}  // namespace fleetloc::mapping
