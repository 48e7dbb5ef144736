// FindSelfSimilarity on a real plain-concrete photograph: alone, no sampled place is ambiguous;
// the same photograph twice side by side, every sampled place inside a copy is, its twin one copy
// width away; bad options and a mosaic smaller than a frame are refused.
#include "relocalization/self_similarity.h"

#include <gtest/gtest.h>

#include "relocalization/test_floors.h"

namespace fleetloc::relocalization {
namespace {

using testing::kResolutionM;
using testing::PlainConcrete;
using testing::SmallCamera;

SelfSimilarityReport Report(const cv::Mat& image, int grid) {
  mosaic::ImageRasterSource floor(image, {0.0, image.rows * kResolutionM, kResolutionM});
  auto search = DensePlaceSearch::Create(floor, SmallCamera(), DensePlaceSearchOptions{});
  EXPECT_TRUE(search.ok()) << search.status().message();
  SelfSimilarityOptions options;
  options.grid = grid;
  auto report = FindSelfSimilarity(**search, floor, SmallCamera(), options);
  EXPECT_TRUE(report.ok()) << report.status().message();
  return *report;
}

TEST(SelfSimilarity, APhotographAloneHasNoAmbiguousPlace) {
  const SelfSimilarityReport report = Report(PlainConcrete(), 3);
  EXPECT_EQ(report.sampled, 9);
  EXPECT_TRUE(report.ambiguous.empty());
}

TEST(SelfSimilarity, APhotographTwiceSideBySideIsAmbiguousOneCopyApart) {
  const cv::Mat photo = PlainConcrete();
  cv::Mat twice;
  cv::hconcat(photo, photo, twice);
  // A 2 × 2 grid over the 2048 px floor: crops at x 432–752 and 1296–1616, each inside a copy.
  const SelfSimilarityReport report = Report(twice, 2);
  EXPECT_EQ(report.sampled, 4);
  const double copy_m = photo.cols * kResolutionM;
  int inside = 0;
  for (const SimilarPlace& p : report.ambiguous) {
    const double apart = std::abs(p.twin.x - p.place.x);
    inside += std::abs(apart - copy_m) < 0.002 && std::abs(p.twin.y - p.place.y) < 0.002;
    EXPECT_GT(p.twin_correlation, 0.6 * p.own);
  }
  EXPECT_EQ(inside, 4);
}

TEST(SelfSimilarity, RefusesBadOptionsAndAMosaicSmallerThanAFrame) {
  const cv::Mat photo = PlainConcrete();
  mosaic::ImageRasterSource floor(photo, {0.0, photo.rows * kResolutionM, kResolutionM});
  auto search = DensePlaceSearch::Create(floor, SmallCamera(), DensePlaceSearchOptions{});
  ASSERT_TRUE(search.ok());
  SelfSimilarityOptions options;
  options.grid = 0;
  EXPECT_FALSE(FindSelfSimilarity(**search, floor, SmallCamera(), options).ok());
  geometry::CameraModel wide = SmallCamera();
  wide.width_px = photo.cols + 2;
  wide.cx_px = 0.5 * wide.width_px;
  const auto refused = FindSelfSimilarity(**search, floor, wide, SelfSimilarityOptions{});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("smaller than a frame"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::relocalization
