// Place index: coverage of the floor, matching a feature's own descriptor, the blob round trip,
// and clear errors for corrupt blobs and textureless floors.
#include "relocalization/place_index.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace fleetloc::relocalization {
namespace {

mosaic::ImageRasterSource GravelFloor() {
  const cv::Mat photo =
      cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/gravel_1024.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(photo.empty());
  return mosaic::ImageRasterSource(photo, {0.0, photo.rows * 0.0005, 0.0005});
}

PlaceIndex BuildGravel() {
  mosaic::ImageRasterSource floor = GravelFloor();
  Result<PlaceIndex> index = PlaceIndex::Build(floor, PlaceIndexOptions{});
  EXPECT_TRUE(index.ok()) << index.status().message();
  return std::move(index).value();
}

TEST(PlaceIndex, CoversEveryRegionOfTheFloorInStrips) {
  mosaic::ImageRasterSource floor = GravelFloor();
  PlaceIndexOptions options;
  options.strip_rows_px = 64;  // 8 strips of the 512-row level 1
  int last_done = 0, total = 0;
  Result<PlaceIndex> index = PlaceIndex::Build(
      floor, options, [&](int done, int strips) { last_done = done, total = strips; });
  ASSERT_TRUE(index.ok()) << index.status().message();
  EXPECT_EQ(total, 8);
  EXPECT_EQ(last_done, 8);
  // Every 128 px (64 mm) square of the 0.512 m floor, away from the border, holds features.
  const int kCells = 8;
  std::vector<int> counts(kCells * kCells, 0);
  for (std::size_t i = 0; i < index->size(); ++i) {
    const Eigen::Vector2d p = index->position_m(i) / 0.064;
    ++counts[std::min(kCells - 1, static_cast<int>(p.y())) * kCells +
             std::min(kCells - 1, static_cast<int>(p.x()))];
  }
  for (int c : counts) EXPECT_GE(c, 10);
  EXPECT_GT(index->size(), 1200u);  // at most 6 per 32 px cell of the 512² level: 1536
}

TEST(PlaceIndex, AFeaturesOwnDescriptorMatchesItself) {
  const PlaceIndex index = BuildGravel();
  int self = 0;
  const int kProbes = 200;
  const std::vector<DescriptorMatch> matches =
      index.Match(index.descriptors().rowRange(0, kProbes), 1, 0);
  // Itself, or an identical descriptor: the gravel photo repeats parts of itself exactly.
  for (const DescriptorMatch& m : matches) self += m.distance == 0;
  EXPECT_GE(self, kProbes * 95 / 100);  // LSH is approximate, but exact copies collide
}

TEST(PlaceIndex, SerializeThenDeserializeKeepsEveryFeature) {
  const PlaceIndex index = BuildGravel();
  const std::vector<std::uint8_t> blob = index.Serialize();
  const Result<PlaceIndex> loaded = PlaceIndex::Deserialize(blob);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  ASSERT_EQ(loaded->size(), index.size());
  for (std::size_t i = 0; i < index.size(); i += 97) {
    EXPECT_EQ(loaded->position_m(i), index.position_m(i));
    EXPECT_EQ(loaded->heading_rad(i), index.heading_rad(i));
  }
  EXPECT_EQ(cv::norm(loaded->descriptors(), index.descriptors(), cv::NORM_L1), 0.0);
  EXPECT_EQ(loaded->resolution_m(), 0.0005);
}

TEST(PlaceIndex, CorruptBlobsAreClearErrors) {
  const std::vector<std::uint8_t> blob = BuildGravel().Serialize();
  const auto message = [](std::span<const std::uint8_t> bytes) {
    const Result<PlaceIndex> loaded = PlaceIndex::Deserialize(bytes);
    EXPECT_FALSE(loaded.ok());
    return loaded.ok() ? std::string() : loaded.status().message();
  };
  EXPECT_NE(message({}).find("not a fleetloc place index"), std::string::npos);
  EXPECT_NE(message(std::span(blob).first(blob.size() / 2)).find("checksum"), std::string::npos);
  std::vector<std::uint8_t> flipped = blob;
  flipped[flipped.size() / 3] ^= 0x40;
  EXPECT_NE(message(flipped).find("checksum"), std::string::npos);
  std::vector<std::uint8_t> future = blob;
  future[8] = 99;  // format version
  EXPECT_NE(message(future).find("format version 99"), std::string::npos);
  const std::vector<std::uint8_t> garbage(5000, 0xAB);
  EXPECT_NE(message(garbage).find("not a fleetloc place index"), std::string::npos);
}

TEST(PlaceIndex, TexturelessFloorIsAClearError) {
  mosaic::ImageRasterSource blank(cv::Mat(1024, 1024, CV_8UC1, cv::Scalar(140)),
                                  {0.0, 0.512, 0.0005});
  const Result<PlaceIndex> index = PlaceIndex::Build(blank, PlaceIndexOptions{});
  ASSERT_FALSE(index.ok());
  EXPECT_NE(index.status().message().find("no distinctive features"), std::string::npos);
}

TEST(PlaceIndex, ABuildStopsWhenCancelled) {
  mosaic::ImageRasterSource floor = GravelFloor();
  PlaceIndexOptions options;
  options.strip_rows_px = 64;  // several strips
  std::atomic<bool> cancel{false};
  int strips_done = 0;
  const Result<PlaceIndex> index = PlaceIndex::Build(
      floor, options, [&](int done, int) { strips_done = done, cancel = done == 2; }, &cancel);
  ASSERT_FALSE(index.ok());
  EXPECT_NE(index.status().message().find("cancelled"), std::string::npos);
  EXPECT_EQ(strips_done, 2);
}

TEST(PlaceIndex, BadOptionsAreRejected) {
  mosaic::ImageRasterSource floor = GravelFloor();
  PlaceIndexOptions options;
  options.features.patch_size_px = 30;
  EXPECT_FALSE(PlaceIndex::Build(floor, options).ok());
  options = {};
  options.features.level = 9;
  EXPECT_FALSE(PlaceIndex::Build(floor, options).ok());
}

}  // namespace
}  // namespace fleetloc::relocalization
