// Convex polygons: the overlap of a camera frame and the mosaic's valid area (at most 8 sides for
// two rectangles), clipping and point-in-polygon tests.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace fleetloc::geometry {

// Vertices in counter-clockwise order (in a y-up frame; in image coordinates, with v down, the
// same list reads clockwise on screen). Empty when degenerate.
using ConvexPolygon = std::vector<Eigen::Vector2d>;

// The four corners of the axis-aligned rectangle [x0, x1] × [y0, y1], counter-clockwise.
ConvexPolygon Rectangle(double x0, double y0, double x1, double y1);

// Intersection of two convex polygons (Sutherland–Hodgman). Written here rather than using
// cv::intersectConvexConvex because that works in float32 only, and we clip in map metres and
// sub-pixel coordinates where float rounding would shift edges; it is 30 lines.
ConvexPolygon ClipConvex(const ConvexPolygon& subject, const ConvexPolygon& clip);

double Area(const ConvexPolygon& polygon);

// True if the point lies inside or on the boundary of the convex polygon.
bool Contains(const ConvexPolygon& polygon, const Eigen::Vector2d& point);

// The x extent [lo, hi] of the polygon along the horizontal line at `y`; lo > hi when the line
// misses it.
std::pair<double, double> SpanAtY(const ConvexPolygon& polygon, double y);

// Ensures counter-clockwise order (reverses a clockwise list).
ConvexPolygon CounterClockwise(ConvexPolygon polygon);

}  // namespace fleetloc::geometry
