// Re-mapping computation on a real floor photo whose floor "changed" in a known place: the patches
// register to the unchanged texture around the change, the new tiles show the changed floor, tiles
// away from the patches are untouched, and the pyramid follows.
#include "mapping/remap.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "mosaic/pyramid_builder.h"

namespace fleetloc::mapping {
namespace {

constexpr double kRes = 0.0005;

cv::Mat Load(const char* path, const cv::Rect& crop) {
  cv::Mat gray = cv::imread(std::string(FLEETLOC_SOURCE_DIR) + "/" + path, cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(gray.empty()) << path;
  return gray(crop).clone();
}

struct Scene {
  cv::Mat old_floor = Load("deploy/demo/floors/rock_dirt_2048.png", {300, 300, 1024, 1024});
  cv::Mat new_floor;
  cv::Rect change{430, 380, 120, 90};  // where a new "marking" (another real texture) appears
  geometry::Geotransform geo{0.0, 1024 * kRes, kRes};
  Scene() {
    new_floor = old_floor.clone();
    Load("tests/data/brick.png", {0, 0, change.width, change.height}).copyTo(new_floor(change));
  }
  // A 320×240 patch of the new floor centred at pixel `centre`, reported off by `error`.
  Patch PatchAt(cv::Point centre, const geometry::Pose2& error) const {
    const cv::Rect crop(centre.x - 160, centre.y - 120, 320, 240);
    const Eigen::Vector2d map = geo.PixelToMap({centre.x * 1.0, centre.y * 1.0});
    Patch p;
    p.image = new_floor(crop).clone();
    p.pose = {map.x() + error.x, map.y() + error.y, M_PI / 2 + error.theta};
    p.covariance = Eigen::Vector3d(std::pow(3 * kRes, 2), std::pow(3 * kRes, 2),
                                   std::pow(0.5 * M_PI / 180, 2)).asDiagonal();
    return p;
  }
};

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
    EXPECT_LT(std::abs(r.pose.theta - M_PI / 2), 0.01 * M_PI / 180) << "patch " << i;
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
