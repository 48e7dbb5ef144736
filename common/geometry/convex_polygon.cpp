// Convex polygon clipping and tests.
#include "geometry/convex_polygon.h"

#include <algorithm>
#include <cmath>

namespace fleetloc::geometry {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

Eigen::Vector2d EdgeIntersection(const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                                 const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double dp = Cross(a, b, p), dq = Cross(a, b, q);
  const double t = dp / (dp - dq);
  return p + t * (q - p);
}

}  // namespace

ConvexPolygon Rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

double Area(const ConvexPolygon& polygon) {
  double twice = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice;
}

ConvexPolygon CounterClockwise(ConvexPolygon polygon) {
  if (Area(polygon) < 0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

ConvexPolygon ClipConvex(const ConvexPolygon& subject, const ConvexPolygon& clip) {
  ConvexPolygon output = CounterClockwise(subject);
  const ConvexPolygon edges = CounterClockwise(clip);
  for (size_t e = 0; e < edges.size() && !output.empty(); ++e) {
    const auto& a = edges[e];
    const auto& b = edges[(e + 1) % edges.size()];
    ConvexPolygon input;
    input.swap(output);
    for (size_t i = 0; i < input.size(); ++i) {
      const auto& p = input[i];
      const auto& q = input[(i + 1) % input.size()];
      const bool p_in = Cross(a, b, p) >= 0, q_in = Cross(a, b, q) >= 0;
      if (p_in) output.push_back(p);
      if (p_in != q_in) output.push_back(EdgeIntersection(p, q, a, b));
    }
  }
  if (output.size() < 3 || std::abs(Area(output)) < 1e-18) return {};
  return output;
}

bool Contains(const ConvexPolygon& polygon, const Eigen::Vector2d& point) {
  if (polygon.size() < 3) return false;
  const double sign = Area(polygon) >= 0 ? 1.0 : -1.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    if (sign * Cross(polygon[i], polygon[(i + 1) % polygon.size()], point) < -1e-12) return false;
  }
  return true;
}

std::pair<double, double> SpanAtY(const ConvexPolygon& polygon, double y) {
  double lo = 1e300, hi = -1e300;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    if ((a.y() - y) * (b.y() - y) > 0 || (a.y() == y && b.y() == y)) {
      if (a.y() == y) {
        lo = std::min(lo, a.x());
        hi = std::max(hi, a.x());
      }
      continue;
    }
    const double x = a.x() + (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y());
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return {lo, hi};
}

}  // namespace fleetloc::geometry
