// Near-vertical image edges for landmark detection: Hough segments that point at the nadir
// vanishing point (world-vertical lines), joined per edge, and the edge's lowest point refined to
// sub-pixel precision on the image gradient. All coordinates are ideal (undistorted) pixels.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace fleetloc::mapmatch {

// A straight edge: the points point + t · down for t in [top, foot]; `down` has unit length and
// points toward the floor (the world's downward direction as seen in the image).
struct VerticalEdge {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d down = Eigen::Vector2d::UnitY();
  double top = 0.0;
  double foot = 0.0;

  Eigen::Vector2d At(double t) const { return point + t * down; }
  Eigen::Vector2d FootPixel() const { return At(foot); }
  double Length() const { return foot - top; }
};

// The image's downward world direction at `pixel` given the homogeneous nadir vanishing point
// (unit length).
Eigen::Vector2d DownDirectionAt(const Eigen::Vector3d& nadir_vp, const Eigen::Vector2d& pixel);

// The segments (x1, y1, x2, y2 from cv::HoughLinesP) within `max_deviation_rad` of the downward
// direction at their midpoint, as edges.
std::vector<VerticalEdge> VerticalSegments(const std::vector<cv::Vec4i>& segments,
                                           const Eigen::Vector3d& nadir_vp,
                                           double max_deviation_rad);

// Joins segments of one edge: a segment whose endpoints lie within `max_distance_px` of a longer
// edge's line and whose extent overlaps it or continues it within `max_gap_px` extends that edge.
std::vector<VerticalEdge> MergeCollinear(std::vector<VerticalEdge> edges, double max_distance_px,
                                         double max_gap_px);

// The gradient of the smoothed ideal image (CV_32FC1 each).
struct Gradients {
  cv::Mat dx, dy;
};

struct EdgeRefinement {
  double search_px = 3.0;              // perpendicular search for the gradient peak
  double foot_search_px = 12.0;        // the foot is looked for this far around the segment's end
  double end_strength_fraction = 0.5;  // foot: edge strength falls below this × the median
  double step_px = 0.25;               // sampling step along the edge for the foot
};

// Fits the edge's line to the sub-pixel gradient peaks across it, then moves the foot to where the
// edge's strength (gradient across the line, with the edge's polarity) falls below the fraction
// of its median for good. nullopt when fewer than half the samples along the edge find a peak.
std::optional<VerticalEdge> RefineEdge(const Gradients& gradients, const VerticalEdge& edge,
                                       const EdgeRefinement& options);

}  // namespace fleetloc::mapmatch
