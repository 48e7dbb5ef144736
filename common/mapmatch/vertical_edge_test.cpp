// Vertical edges on synthetic images with known geometry: segment sorting by the nadir vanishing
// point, merging of Hough pieces, and the sub-pixel line and foot.
#include "mapmatch/vertical_edge.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace fleetloc::mapmatch {
namespace {

// The gradients of a 200×200 image: a bright rectangle x >= edge_x, y < foot_y (continuous image
// coordinates, pixel i covering [i, i + 1)) on a dark background, drawn 8× larger and area-averaged
// so that its borders are sub-pixel exact, then smoothed. In pixel-centre coordinates (OpenCV's,
// as the detector's) the borders are at edge_x - 0.5 and foot_y - 0.5.
Gradients CornerGradients(double edge_x, double foot_y) {
  constexpr int kScale = 8;
  cv::Mat large(200 * kScale, 200 * kScale, CV_32FC1, cv::Scalar(60));
  large(cv::Rect(static_cast<int>(edge_x * kScale), 0,
                 200 * kScale - static_cast<int>(edge_x * kScale),
                 static_cast<int>(foot_y * kScale)))
      .setTo(160);
  cv::Mat image;
  cv::resize(large, image, cv::Size(200, 200), 0, 0, cv::INTER_AREA);
  cv::GaussianBlur(image, image, cv::Size(), 1.0);
  Gradients g;
  cv::Sobel(image, g.dx, CV_32F, 1, 0);
  cv::Sobel(image, g.dy, CV_32F, 0, 1);
  return g;
}

TEST(VerticalEdge, SortsSegmentsByTheirAngleToTheDownwardDirection) {
  const Eigen::Vector3d level_vp(0, 1, 0);  // a level camera: verticals are image columns
  const std::vector<cv::Vec4i> segments{
      {10, 10, 10, 90}, {50, 90, 52, 10}, {0, 0, 90, 30}, {20, 20, 40, 90}};
  const SortedSegments sorted = SortSegments(segments, level_vp, 0.035, 0.25);
  ASSERT_EQ(sorted.vertical.size(), 2u);  // the column and the 1.4° one
  EXPECT_GT(sorted.vertical[1].direction.y(), 0) << "directed downward";
  EXPECT_NEAR(sorted.vertical[1].Length(), std::hypot(2.0, 80.0), 1e-12);
  ASSERT_EQ(sorted.boundaries.size(), 2u);  // the 72° one and the 16° one
}

TEST(VerticalEdge, DownDirectionPointsAtAVanishingPointBelowTheImage) {
  const Eigen::Vector3d vp(320.0 * 2, 1500.0 * 2, 2.0);  // (320, 1500) in pixels
  const Eigen::Vector2d d = DownDirectionAt(vp, {0.0, 0.0});
  EXPECT_NEAR(d.x(), 320.0 / std::hypot(320.0, 1500.0), 1e-12);
  EXPECT_NEAR(d.y(), 1500.0 / std::hypot(320.0, 1500.0), 1e-12);
}

TEST(VerticalEdge, MergesCollinearPiecesAndKeepsParallelEdgesApart) {
  const EdgeSegment a{{100, 50}, {0, 1}, -40, 40};     // y 10..90
  const EdgeSegment b{{100.8, 110}, {0, 1}, -15, 15};  // y 95..125, 0.8 px aside, 5 px gap
  const EdgeSegment c{{106, 50}, {0, 1}, -40, 40};     // a parallel edge 6 px away
  const std::vector<EdgeSegment> merged = MergeCollinear({b, a, c}, 3.0, 12.0);
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_NEAR(merged[0].At(merged[0].begin).y(), 10, 1e-9);
  EXPECT_NEAR(merged[0].EndPixel().y(), 125, 1e-9);
}

TEST(VerticalEdge, RefinesTheLineAndTheFootToSubPixelPrecision) {
  for (const double foot_y : {120.0, 120.25, 120.5, 120.75}) {
    const Gradients g = CornerGradients(100.25, foot_y);
    // A rough Hough-like segment: 1 px off, ending 3 px early.
    const EdgeSegment rough{{101.0, 80.0}, {0, 1}, -60, foot_y - 83.0};
    const std::optional<EdgeSegment> edge = RefineEdge(g, rough, {}, {});
    ASSERT_TRUE(edge.has_value());
    // The border x = 100.25 (image units) is at pixel-centre coordinate 99.75.
    EXPECT_NEAR(edge->EndPixel().x(), 99.75, 0.05);
    EXPECT_NEAR(edge->EndPixel().y(), foot_y - 0.5, 0.3) << foot_y;
  }
}

TEST(VerticalEdge, SnapsTheFootToACrossingFloorBoundary) {
  const Gradients g = CornerGradients(100.0, 120.0);
  const EdgeSegment rough{{100.0, 80.0}, {0, 1}, -60, 38};
  // A boundary through (99.5, 121.5) sloping 30°: the foot moves onto it.
  const Eigen::Vector2d direction = Eigen::Vector2d(std::cos(0.5), std::sin(0.5));
  const EdgeSegment boundary{Eigen::Vector2d(99.5, 121.5) + 5 * direction, direction, -5, 20};
  const std::optional<EdgeSegment> edge = RefineEdge(g, rough, {boundary}, {});
  ASSERT_TRUE(edge.has_value());
  const Eigen::Vector2d foot = edge->EndPixel();
  EXPECT_NEAR(
      (foot - boundary.point).x() * direction.y() - (foot - boundary.point).y() * direction.x(),
      0.0, 1e-6)
      << "on the boundary line";
}

TEST(VerticalEdge, AFlatImageHasNoEdgeToFit) {
  Gradients g{cv::Mat::zeros(200, 200, CV_32FC1), cv::Mat::zeros(200, 200, CV_32FC1)};
  EXPECT_FALSE(FitEdgeLine(g, {{100, 100}, {0, 1}, -50, 50}, 3.0).has_value());
}

}  // namespace
}  // namespace fleetloc::mapmatch
