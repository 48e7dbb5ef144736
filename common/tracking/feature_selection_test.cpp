// Tests for template site selection: inside the overlap only, spread over the frame.
#include "tracking/feature_selection.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace fleetloc::tracking {
namespace {

TEST(CandidateSites, KeepOnlySitesWhoseSquareFitsTheOverlap) {
  const cv::Mat texture(59, 79, CV_32F, cv::Scalar(10.0f));  // grid of a 640×480 frame
  const auto region = geometry::Rectangle(0, 0, 300, 480);   // mosaic ends at u = 300
  const auto sites = CandidateSites(texture, 8, {{region, 40.0}}, 1.0, 10000);
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
  const auto sites =
      CandidateSites(texture, 8, {{geometry::Rectangle(0, 0, 100, 100), 0.0}}, 0.0, 5);
  ASSERT_EQ(sites.size(), 5u);
  for (const auto& s : sites) EXPECT_GE(s.texture, 95.0);
}

TEST(CandidateSites, ASiteMustFitEveryBound) {
  const cv::Mat texture(59, 79, CV_32F, cv::Scalar(10.0f));    // grid of a 640×480 frame
  const auto frame = geometry::Rectangle(0, 0, 640, 480);      // the template inside the frame
  const auto mosaic = geometry::Rectangle(-100, 0, 400, 480);  // its search window in the mosaic
  const auto sites = CandidateSites(texture, 8, {{frame, 30.0}, {mosaic, 60.0}}, 1.0, 10000);
  ASSERT_FALSE(sites.empty());
  double min_u = 1e9, max_u = 0;
  for (const auto& s : sites) {
    min_u = std::min(min_u, s.center_px.x());
    max_u = std::max(max_u, s.center_px.x());
    EXPECT_GE(s.center_px.y(), 60.0);  // the window needs 60 px inside the mosaic's top edge
  }
  EXPECT_EQ(min_u, 32.0);   // the frame's bound, not the mosaic's (−40)
  EXPECT_EQ(max_u, 336.0);  // the mosaic's bound (≤ 340)
}

TEST(RelativeTextureThreshold, FollowsTheFramesOwnTextureAboveTheFloor) {
  cv::Mat texture(10, 10, CV_32F);
  for (int i = 0; i < 100; ++i) texture.at<float>(i / 10, i % 10) = 0.01f * (i + 1);  // plain
  EXPECT_NEAR(RelativeTextureThreshold(texture, 0.9, 0.5, 0.1), 0.5 * 0.9, 0.011);
  EXPECT_DOUBLE_EQ(RelativeTextureThreshold(texture, 0.9, 0.5, 2.0), 2.0);
  texture *= 100.0;  // the same floor, ten times the contrast: the threshold follows
  EXPECT_NEAR(RelativeTextureThreshold(texture, 0.9, 0.5, 0.1), 50.0 * 0.9, 1.1);
  EXPECT_DOUBLE_EQ(RelativeTextureThreshold(cv::Mat(3, 3, CV_32F, cv::Scalar(0)), 0.9, 0.5, 0.1),
                   0.1);
}

TEST(SelectSites, SpreadsPicksAcrossTheFrameInsteadOfClusteringOnTheBest) {
  std::vector<TemplateSite> c;
  c.reserve(11);
  for (int i = 0; i < 10; ++i) c.push_back({{100.0 + 8 * i, 100.0}, 100.0 - i});  // a hot spot
  c.push_back({{500.0, 400.0}, 50.0});                                            // far, weaker
  const auto chosen = SelectSites(c, 2, 120.0, 32.0);
  ASSERT_EQ(chosen.size(), 2u);
  EXPECT_EQ(chosen[0].center_px.x(), 100.0);
  EXPECT_EQ(chosen[1].center_px.x(), 500.0);
}

TEST(SelectSites, NeverPicksOverlappingTemplates) {
  std::vector<TemplateSite> c;
  c.reserve(50);
  for (int i = 0; i < 50; ++i) c.push_back({{8.0 * i, 0.0}, 1.0});
  const auto chosen = SelectSites(c, 50, 100.0, 32.0);
  for (size_t i = 0; i < chosen.size(); ++i)
    for (size_t j = i + 1; j < chosen.size(); ++j)
      EXPECT_GE((chosen[i].center_px - chosen[j].center_px).norm(), 32.0);
}

// Debris across a third of a frame scores ten times the floor's texture: uncapped, every pick of
// ten lands on it; capped at the candidates' median, the picks spread over the frame and most land
// on the floor.
TEST(CapTexture, AStrongOccluderNoLongerTakesEveryPick) {
  std::vector<TemplateSite> c;
  for (int y = 16; y < 480; y += 16) {
    for (int x = 16; x < 640; x += 16) {
      const bool debris = x < 213;  // the left third
      c.push_back({{double(x), double(y)}, debris ? 100.0 + (x + y) % 7 : 10.0 + (x * y) % 3});
    }
  }
  const auto on_floor = [](const std::vector<TemplateSite>& chosen) {
    return std::count_if(chosen.begin(), chosen.end(),
                         [](const TemplateSite& s) { return s.center_px.x() >= 213; });
  };
  EXPECT_EQ(on_floor(SelectSites(c, 10, 120.0, 48.0)), 0);
  std::vector<TemplateSite> capped = c;
  CapTexture(0.5, &capped);
  for (size_t i = 0; i < c.size(); ++i) EXPECT_LE(capped[i].texture, c[i].texture);
  EXPECT_GE(on_floor(SelectSites(capped, 10, 120.0, 48.0)), 6);
  std::vector<TemplateSite> unchanged = c;
  CapTexture(0.0, &unchanged);
  EXPECT_EQ(unchanged[0].texture, c[0].texture);
}

}  // namespace
}  // namespace fleetloc::tracking
