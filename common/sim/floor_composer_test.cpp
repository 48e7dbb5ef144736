// Tests for the floor composer: pixels come from the photos as the placement says, a seed always
// gives the same floor, neighbouring blocks differ, and block rows tile the floor exactly.
#include "sim/floor_composer.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>
#include <utility>

namespace fleetloc::sim {
namespace {

const std::string kFloors = FLEETLOC_SOURCE_DIR "/deploy/demo/floors/";

std::vector<cv::Mat> RealPhotos() {
  std::vector<cv::Mat> photos;
  for (const char* name : {"asphalt_1024.jpg", "gravel_1024.png", "moss_2560x1600.jpg"}) {
    photos.push_back(cv::imread(kFloors + name, cv::IMREAD_GRAYSCALE));
    EXPECT_FALSE(photos.back().empty()) << name;
  }
  return photos;
}

FloorComposer MakeComposer(FloorComposerOptions options) {
  Result<FloorComposer> composer = FloorComposer::Create(RealPhotos(), options);
  EXPECT_TRUE(composer.ok()) << composer.status().message();
  return std::move(composer).value();
}

FloorComposerOptions SmallFloor(std::uint64_t seed) {
  FloorComposerOptions options;
  options.width_px = 1000;  // 4 block columns, the last one cut at 232 px
  options.height_px = 700;  // 3 block rows, the last one cut at 188 px
  options.block_px = 256;
  options.seed = seed;
  return options;
}

// The whole floor, block row by block row.
cv::Mat RenderFloor(const FloorComposer& composer) {
  std::vector<cv::Mat> rows;
  for (int row = 0; row < composer.block_rows(); ++row)
    rows.push_back(composer.RenderBlockRow(row));
  cv::Mat floor;
  cv::vconcat(rows, floor);
  return floor;
}

// The photo pixel under block pixel (u, v), undoing the placement's flips then its transpose.
std::uint8_t ExpectedPixel(const cv::Mat& photo, const BlockPlacement& p, int block_px, int u,
                           int v) {
  if (p.flip_x) u = block_px - 1 - u;
  if (p.flip_y) v = block_px - 1 - v;
  if (p.transpose) std::swap(u, v);
  const int source = photo.at<std::uint8_t>(p.crop_origin.y + v, p.crop_origin.x + u);
  return cv::saturate_cast<std::uint8_t>(p.gain * source);
}

TEST(FloorComposer, FloorPixelsAreThePlacedPhotoPixelsTimesTheGain) {
  const std::vector<cv::Mat> photos = RealPhotos();
  const FloorComposer composer = MakeComposer(SmallFloor(7));
  const cv::Mat floor = RenderFloor(composer);
  ASSERT_EQ(floor.size(), cv::Size(1000, 700));
  const int b = composer.options().block_px;
  int checked = 0;
  for (int row = 0; row < composer.block_rows(); ++row) {
    for (int col = 0; col < composer.block_cols(); ++col) {
      const BlockPlacement p = composer.PlacementOf(col, row);
      for (const auto& [u, v] : {std::pair{0, 0}, {b - 1, 0}, {0, b - 1}, {31, 200}, {117, 5}}) {
        const int x = col * b + u, y = row * b + v;
        if (x >= floor.cols || y >= floor.rows) continue;
        ASSERT_EQ(floor.at<std::uint8_t>(y, x), ExpectedPixel(photos[p.photo], p, b, u, v))
            << "block " << col << "," << row << " pixel " << u << "," << v;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 40);
}

TEST(FloorComposer, SameSeedGivesTheSameFloorAndAnotherSeedAnother) {
  const cv::Mat first = RenderFloor(MakeComposer(SmallFloor(3)));
  const cv::Mat again = RenderFloor(MakeComposer(SmallFloor(3)));
  const cv::Mat other = RenderFloor(MakeComposer(SmallFloor(4)));
  EXPECT_EQ(cv::norm(first, again, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(first, other, cv::NORM_L1) / first.total(), 10.0);
}

TEST(FloorComposer, NoBlockEqualsAnyOfItsNeighbours) {
  FloorComposerOptions options = SmallFloor(11);
  options.width_px = options.height_px = 6 * 64;
  options.block_px = 64;  // 6 × 6 blocks from 3 photos: neighbours often share a photo
  const FloorComposer composer = MakeComposer(options);
  for (int row = 0; row < 6; ++row) {
    for (int col = 0; col < 6; ++col) {
      const cv::Mat block = composer.RenderBlock(col, row);
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int r = row + dr, c = col + dc;
          if ((dr == 0 && dc == 0) || r < 0 || c < 0 || r >= 6 || c >= 6) continue;
          EXPECT_GT(cv::norm(block, composer.RenderBlock(c, r), cv::NORM_L1), 0.0)
              << "block " << col << "," << row << " vs " << c << "," << r;
        }
      }
    }
  }
}

TEST(FloorComposer, UsesEveryPhotoAndVariesCropsAndGains) {
  FloorComposerOptions options = SmallFloor(5);
  options.width_px = options.height_px = 16 * 256;
  const FloorComposer composer = MakeComposer(options);
  std::vector<int> uses(3, 0);
  double min_gain = 2, max_gain = 0;
  for (int row = 0; row < 16; ++row) {
    for (int col = 0; col < 16; ++col) {
      const BlockPlacement p = composer.PlacementOf(col, row);
      ++uses[p.photo];
      min_gain = std::min(min_gain, p.gain);
      max_gain = std::max(max_gain, p.gain);
    }
  }
  for (int n : uses) EXPECT_GT(n, 40);  // 256 blocks over 3 photos
  EXPECT_LT(min_gain, 0.9);
  EXPECT_GT(max_gain, 1.1);
  EXPECT_NE(composer.PlacementOf(0, 0).crop_origin, composer.PlacementOf(2, 0).crop_origin);
}

TEST(FloorComposer, RejectsPhotosSmallerThanABlockAndBadSizes) {
  FloorComposerOptions options = SmallFloor(1);
  options.block_px = 2048;  // larger than the 1024 px photos
  Result<FloorComposer> too_small = FloorComposer::Create(RealPhotos(), options);
  ASSERT_FALSE(too_small.ok());
  EXPECT_NE(too_small.status().message().find("photo 0"), std::string::npos);
  options = SmallFloor(1);
  options.width_px = 0;
  EXPECT_EQ(FloorComposer::Create(RealPhotos(), options).status().code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(FloorComposer::Create({}, SmallFloor(1)).status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace fleetloc::sim

namespace fleetloc::sim {
namespace {

TEST(FloorComposer, FreeBlocksAreTheirPhotoRotatedAndScaledAboutTheDrawnCentre) {
  FloorComposerOptions options = SmallFloor(3);
  options.free_rotation_and_scale = true;
  options.max_gain_change = 0.0;
  const std::vector<cv::Mat> photos = RealPhotos();
  const FloorComposer composer = MakeComposer(options);
  std::set<long> angles;
  for (int col = 0; col < composer.block_cols(); ++col) {
    const BlockPlacement p = composer.PlacementOf(col, 1);
    angles.insert(std::lround(p.angle_rad * 1000));
    EXPECT_GE(p.scale, options.min_scale);
    EXPECT_LE(p.scale, options.max_scale);
    const cv::Mat block = composer.RenderBlock(col, 1);
    // Block pixel centre (x + 0.5, y + 0.5) comes from photo point center + s·R·(pixel − b/2).
    for (const cv::Point pixel : {cv::Point(128, 128), cv::Point(10, 200), cv::Point(250, 5)}) {
      const double dx = pixel.x + 0.5 - 128, dy = pixel.y + 0.5 - 128;
      const double c = std::cos(p.angle_rad), s = std::sin(p.angle_rad);
      const cv::Point2d at = p.center + p.scale * cv::Point2d(c * dx - s * dy, s * dx + c * dy);
      cv::Mat sample;
      cv::getRectSubPix(photos[p.photo], cv::Size(1, 1), at - cv::Point2d(0.5, 0.5), sample);
      const int x = p.flip_x ? 255 - pixel.x : pixel.x;
      EXPECT_NEAR(block.at<std::uint8_t>(pixel.y, x), sample.at<std::uint8_t>(0, 0), 2.0);
    }
  }
  EXPECT_EQ(angles.size(), static_cast<std::size_t>(composer.block_cols()));  // all different
}

TEST(FloorComposer, FreeBlocksNeedPhotosLargeEnoughForAnyRotation) {
  FloorComposerOptions options = SmallFloor(1);
  options.block_px = 512;  // needs 2 · (ceil(512 · 1.25 · √2 / 2) + 2) = 910 px
  options.free_rotation_and_scale = true;
  const Result<FloorComposer> composer =
      FloorComposer::Create({cv::Mat(800, 800, CV_8UC1, cv::Scalar(9))}, options);
  ASSERT_FALSE(composer.ok());
  EXPECT_NE(composer.status().message().find("910 px"), std::string::npos)
      << composer.status().message();
}

}  // namespace
}  // namespace fleetloc::sim
