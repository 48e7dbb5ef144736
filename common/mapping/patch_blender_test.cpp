// Patch blending: exact placement through the pose, feathering, replace/blend, photometric fit.
#include "mapping/patch_blender.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

namespace fleetloc::mapping {
namespace {

constexpr double kRes = 0.0005;

cv::Mat Photo() {
  cv::Mat gray = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/brick.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(gray.empty());
  return gray;
}

// Geotransform of a 512² mosaic with its top-left corner at map (0, 512·res).
geometry::Geotransform Geo() { return {0.0, 512 * kRes, kRes}; }

// The pose of a patch cut at `crop` from the mosaic image, aligned with it (top of the patch
// toward +y of the map: theta = pi/2).
geometry::Pose2 AlignedPose(const cv::Rect& crop) {
  const Eigen::Vector2d centre =
      Geo().PixelToMap({crop.x + crop.width / 2.0, crop.y + crop.height / 2.0});
  return {centre.x(), centre.y(), M_PI / 2};
}

TEST(PatchBlender, PatchLandsOnItsMapPositionExactly) {
  const cv::Mat photo = Photo();
  const cv::Rect crop(100, 140, 160, 120);
  const PlacedPatch patch{photo(crop).clone(), AlignedPose(crop)};
  const cv::Rect tile_rect(64, 128, 256, 256);  // a tile the patch lies inside
  const cv::Mat empty = cv::Mat::zeros(256, 256, CV_8UC1);
  const cv::Mat out = BlendTile(empty, tile_rect.tl(), Geo(), {patch}, BlendMode::kReplace, 16);
  // Inside the patch (away from the feathered, interpolated border) the pixels are the photo's.
  const cv::Rect inner(crop.x + 2, crop.y + 2, crop.width - 4, crop.height - 4);
  cv::Mat diff;
  cv::absdiff(out(inner - tile_rect.tl()), photo(inner), diff);
  double max_diff = 0;
  cv::minMaxLoc(diff, nullptr, &max_diff);
  EXPECT_LE(max_diff, 1.0);
  EXPECT_EQ(out.at<uchar>(5, 5), 0);  // outside the patch: unchanged
}

TEST(PatchBlender, ReplaceCoversTheInteriorAndFeathersIntoTheBase) {
  const cv::Mat photo = Photo();
  const cv::Rect crop(100, 140, 160, 120);
  const PlacedPatch patch{cv::Mat(crop.size(), CV_8UC1, cv::Scalar(200)), AlignedPose(crop)};
  const cv::Mat base(256, 256, CV_8UC1, cv::Scalar(100));
  const cv::Point origin(64, 128);
  const cv::Mat replaced = BlendTile(base, origin, Geo(), {patch}, BlendMode::kReplace, 16);
  const cv::Mat blended = BlendTile(base, origin, Geo(), {patch}, BlendMode::kBlend, 16);
  const cv::Point centre = cv::Point(crop.x + 80, crop.y + 60) - origin;
  EXPECT_EQ(replaced.at<uchar>(centre), 200);
  EXPECT_EQ(blended.at<uchar>(centre), 150);
  // Half the feather width in from the border: between base and patch; just outside: the base.
  const cv::Point half_feather = cv::Point(crop.x + 8, crop.y + 60) - origin;
  EXPECT_GT(replaced.at<uchar>(half_feather), 120);
  EXPECT_LT(replaced.at<uchar>(half_feather), 180);
  EXPECT_EQ(replaced.at<uchar>(cv::Point(crop.x - 2, crop.y + 60) - origin), 100);
}

TEST(PatchBlender, FeatherIsOneInsideAndFallsToZeroAtTheBorder) {
  const cv::Mat w = FeatherWeights({100, 80}, 10);
  EXPECT_FLOAT_EQ(w.at<float>(40, 50), 1.0f);
  EXPECT_LT(w.at<float>(0, 50), 0.01f);
  EXPECT_LT(w.at<float>(40, 99), 0.01f);
  EXPECT_GT(w.at<float>(40, 5), 0.4f);
}

TEST(PatchBlender, PhotometricFitRecoversGainAndBias) {
  const cv::Mat photo = Photo()(cv::Rect(0, 0, 200, 200));
  cv::Mat patch;
  photo.convertTo(patch, CV_8U, 0.5, 40);  // patch = 0.5 mosaic + 40: mosaic = 2 patch − 80
  const auto [gain, bias] = PhotometricFit(patch, photo);
  EXPECT_NEAR(gain, 2.0, 0.02);
  EXPECT_NEAR(bias, -80.0, 2.0);
}

}  // namespace
}  // namespace fleetloc::mapping
