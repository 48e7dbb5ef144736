// Near-vertical image edges for landmark detection: Hough segments that point at the nadir
// vanishing point (world-vertical lines), joined per edge, and the edge's lowest point (its foot)
// refined to sub-pixel precision: where the edge's gradient fades, then snapped to the crossing
// with a floor boundary (a non-vertical edge through the corner's foot) when there is one. All
// coordinates are ideal (undistorted) pixels.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace fleetloc::mapmatch {

// A straight edge segment: the points point + t · direction for t in [begin, end], direction of
// unit length. For a vertical edge the direction points toward the floor, so `end` is its foot.
struct EdgeSegment {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitY();
  double begin = 0.0;
  double end = 0.0;

  Eigen::Vector2d At(double t) const { return point + t * direction; }
  Eigen::Vector2d EndPixel() const { return At(end); }
  double Length() const { return end - begin; }
};

// The image's downward world direction at `pixel` given the homogeneous nadir vanishing point
// (unit length).
Eigen::Vector2d DownDirectionAt(const Eigen::Vector3d& nadir_vp, const Eigen::Vector2d& pixel);

// Hough segments (x1, y1, x2, y2 from cv::HoughLinesP) split by their angle to the downward
// direction at their midpoint: within `max_vertical_deviation_rad` they are vertical edges
// (directed downward); beyond `min_boundary_angle_rad` they may be floor boundaries.
struct SortedSegments {
  std::vector<EdgeSegment> vertical;
  std::vector<EdgeSegment> boundaries;
};
SortedSegments SortSegments(const std::vector<cv::Vec4i>& segments, const Eigen::Vector3d& nadir_vp,
                            double max_vertical_deviation_rad, double min_boundary_angle_rad);

// Joins segments of one edge: a segment whose endpoints lie within `max_distance_px` of a longer
// edge's line and whose extent overlaps it or continues it within `max_gap_px` extends that edge.
std::vector<EdgeSegment> MergeCollinear(std::vector<EdgeSegment> edges, double max_distance_px,
                                        double max_gap_px);

// The gradient of the smoothed ideal image (CV_32FC1 each).
struct Gradients {
  cv::Mat dx, dy;
};

struct EdgeRefinement {
  double search_px = 3.0;              // perpendicular search for the gradient peak
  double foot_search_px = 12.0;        // the fade is looked for from this far above the end
  double fade_fraction = 0.25;         // fade: strength below this × the edge's median
  double end_strength_fraction = 0.5;  // end: this × the strength just above the fade
  double step_px = 0.25;               // sampling step along the edge for the fade
  double snap_distance_px = 5.0;       // a boundary crossing this close to the fade is the foot
  double snap_reach_px = 6.0;          // ... if the boundary segment reaches that close to it
};

// The segment's line fitted to the sub-pixel gradient peaks across it (same extent, projected);
// nullopt when fewer than half the samples along it find a peak of the dominant polarity.
std::optional<EdgeSegment> FitEdgeLine(const Gradients& gradients, const EdgeSegment& segment,
                                       double search_px);

// Fits a vertical edge's line, then puts its foot where the edge's strength (gradient across the
// line, with the edge's polarity) fades for good (below fade_fraction of its median), at the
// half-maximum (end_strength_fraction) of the strength just above the fade, and finally on the
// nearest crossing with a fitted boundary line within snap_distance_px of that. nullopt when the
// line fit fails.
std::optional<EdgeSegment> RefineEdge(const Gradients& gradients, const EdgeSegment& edge,
                                      const std::vector<EdgeSegment>& boundaries,
                                      const EdgeRefinement& options);

}  // namespace fleetloc::mapmatch
