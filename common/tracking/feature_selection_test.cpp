// Tests for template site selection: inside the overlap only, spread over the frame.
#include "tracking/feature_selection.h"

#include <gtest/gtest.h>

namespace fleetloc::tracking {
namespace {

TEST(CandidateSites, KeepOnlySitesWhoseSquareFitsTheOverlap) {
  const cv::Mat texture(59, 79, CV_32F, cv::Scalar(10.0f));  // grid of a 640×480 frame
  const auto region = geometry::Rectangle(0, 0, 300, 480);   // mosaic ends at u = 300
  const auto sites = CandidateSites(texture, 8, region, 40.0, 1.0, 10000);
  ASSERT_FALSE(sites.empty());
  for (const auto& s : sites) {
    EXPECT_LE(s.center_px.x() + 40.0, 300.0);
    EXPECT_GE(s.center_px.y() - 40.0, 0.0);
  }
  // Every grid point that does fit is a candidate: u in [40, 260], v in [40, 440].
  EXPECT_EQ(sites.size(), 28u * 51u);
}

TEST(CandidateSites, KeepsTheBestTexturedWhenThereAreTooMany) {
  cv::Mat texture(10, 10, CV_32F);
  for (int i = 0; i < 100; ++i) texture.at<float>(i / 10, i % 10) = static_cast<float>(i);
  const auto sites = CandidateSites(texture, 8, geometry::Rectangle(0, 0, 100, 100), 0.0, 0.0, 5);
  ASSERT_EQ(sites.size(), 5u);
  for (const auto& s : sites) EXPECT_GE(s.texture, 95.0);
}

TEST(SelectSites, SpreadsPicksAcrossTheFrameInsteadOfClusteringOnTheBest) {
  std::vector<TemplateSite> c;
  for (int i = 0; i < 10; ++i) c.push_back({{100.0 + 8 * i, 100.0}, 100.0 - i});  // a hot spot
  c.push_back({{500.0, 400.0}, 50.0});                                            // far, weaker
  const auto chosen = SelectSites(c, 2, 120.0, 32.0);
  ASSERT_EQ(chosen.size(), 2u);
  EXPECT_EQ(chosen[0].center_px.x(), 100.0);
  EXPECT_EQ(chosen[1].center_px.x(), 500.0);
}

TEST(SelectSites, NeverPicksOverlappingTemplates) {
  std::vector<TemplateSite> c;
  for (int i = 0; i < 50; ++i) c.push_back({{8.0 * i, 0.0}, 1.0});
  const auto chosen = SelectSites(c, 50, 100.0, 32.0);
  for (size_t i = 0; i < chosen.size(); ++i)
    for (size_t j = i + 1; j < chosen.size(); ++j)
      EXPECT_GE((chosen[i].center_px - chosen[j].center_px).norm(), 32.0);
}

}  // namespace
}  // namespace fleetloc::tracking
