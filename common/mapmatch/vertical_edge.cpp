// Near-vertical edges: selection, merging and sub-pixel foot refinement (see vertical_edge.h).
#include "mapmatch/vertical_edge.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::mapmatch {
namespace {

// Bilinear sample of a CV_32FC1 image at pixel coordinates (centres at integers); 0 outside.
double Bilinear(const cv::Mat& image, const Eigen::Vector2d& p) {
  const double fx = std::floor(p.x()), fy = std::floor(p.y());
  const int x = static_cast<int>(fx), y = static_cast<int>(fy);
  if (x < 0 || y < 0 || x + 1 >= image.cols || y + 1 >= image.rows) return 0.0;
  const double ax = p.x() - fx, ay = p.y() - fy;
  const float* r0 = image.ptr<float>(y) + x;
  const float* r1 = image.ptr<float>(y + 1) + x;
  return (1 - ay) * ((1 - ax) * r0[0] + ax * r0[1]) + ay * ((1 - ax) * r1[0] + ax * r1[1]);
}

// The gradient component across the edge (along `normal`) at `p`.
double Across(const Gradients& g, const Eigen::Vector2d& p, const Eigen::Vector2d& normal) {
  return Bilinear(g.dx, p) * normal.x() + Bilinear(g.dy, p) * normal.y();
}

struct Peak {
  Eigen::Vector2d point;
  double strength = 0.0;  // signed gradient across the edge
};

// The strongest gradient across the edge within ±search_px of `p`, with a parabolic sub-pixel
// offset; nullopt at the search window's border (no peak inside).
std::optional<Peak> PeakAcross(const Gradients& g, const Eigen::Vector2d& p,
                               const Eigen::Vector2d& normal, int search_px) {
  std::vector<double> profile;
  for (int o = -search_px; o <= search_px; ++o)
    profile.push_back(Across(g, p + o * normal, normal));
  const auto best = std::max_element(profile.begin(), profile.end(),
                                     [](double a, double b) { return std::abs(a) < std::abs(b); });
  const int i = static_cast<int>(best - profile.begin());
  if (i == 0 || i + 1 == static_cast<int>(profile.size())) return std::nullopt;
  const double l = std::abs(profile[i - 1]), c = std::abs(profile[i]), r = std::abs(profile[i + 1]);
  const double curvature = l - 2 * c + r;
  const double offset = curvature < 0 ? 0.5 * (l - r) / curvature : 0.0;
  return Peak{p + (i - search_px + offset) * normal, profile[i]};
}

Eigen::Vector2d Normal(const VerticalEdge& edge) { return {-edge.down.y(), edge.down.x()}; }

// The edge's strength at t: the largest polarity-signed gradient across it within ±1 px.
double StrengthAt(const Gradients& g, const VerticalEdge& edge, double t, double polarity) {
  const Eigen::Vector2d n = Normal(edge);
  double strength = -INFINITY;
  for (double o = 0.0; o <= 0.0; o += 0.5) {
    strength = std::max(strength, polarity * Across(g, edge.At(t) + o * n, n));
  }
  return strength;
}

// Where the strength falls below `threshold` for good (for `persist` samples) scanning down from
// `start`, interpolated between the last strong and the first weak sample; when the edge is already
// weak at `start`, where it becomes strong scanning up.
double FootAlong(const Gradients& g, const VerticalEdge& edge, double polarity, double threshold,
                 double start, const EdgeRefinement& options) {
  const double step = options.step_px;
  const auto strength = [&](double t) { return StrengthAt(g, edge, t, polarity); };
  double t = start, s = strength(t);
  if (s < threshold) {  // scan up to the edge
    while (t > edge.top && s < threshold) t -= step, s = strength(t);
    return t;
  }
  const int persist = static_cast<int>(std::ceil(2.0 / step));
  while (s > 0.0) {  // 0 outside the image
    const double next = strength(t + step);
    if (next < threshold) {
      int weak = 1;
      while (weak < persist && strength(t + (weak + 1) * step) < threshold) ++weak;
      if (weak == persist) return t + step * (s - threshold) / (s - next);
    }
    t += step, s = next;
  }
  return t;
}

}  // namespace

Eigen::Vector2d DownDirectionAt(const Eigen::Vector3d& nadir_vp, const Eigen::Vector2d& pixel) {
  // d/ds of the image of X + s·down is proportional to vp.xy - vp.z · pixel (positive depth).
  return (nadir_vp.head<2>() - nadir_vp.z() * pixel).normalized();
}

std::vector<VerticalEdge> VerticalSegments(const std::vector<cv::Vec4i>& segments,
                                           const Eigen::Vector3d& nadir_vp,
                                           double max_deviation_rad) {
  std::vector<VerticalEdge> edges;
  for (const cv::Vec4i& s : segments) {
    const Eigen::Vector2d a(s[0], s[1]), b(s[2], s[3]);
    const double length = (b - a).norm();
    if (length == 0.0) continue;
    const Eigen::Vector2d mid = (a + b) / 2;
    const Eigen::Vector2d down = DownDirectionAt(nadir_vp, mid);
    Eigen::Vector2d along = (b - a) / length;
    if (along.dot(down) < 0) along = -along;
    if (std::acos(std::min(1.0, along.dot(down))) > max_deviation_rad) continue;
    edges.push_back({mid, along, -length / 2, length / 2});
  }
  return edges;
}

std::vector<VerticalEdge> MergeCollinear(std::vector<VerticalEdge> edges, double max_distance_px,
                                         double max_gap_px) {
  std::sort(edges.begin(), edges.end(),
            [](const VerticalEdge& a, const VerticalEdge& b) { return a.Length() > b.Length(); });
  std::vector<VerticalEdge> merged;
  for (const VerticalEdge& e : edges) {
    const Eigen::Vector2d top = e.At(e.top), foot = e.At(e.foot);
    const auto joins = [&](const VerticalEdge& m) {
      const Eigen::Vector2d n = Normal(m);
      const double t0 = (top - m.point).dot(m.down), t1 = (foot - m.point).dot(m.down);
      return std::abs((top - m.point).dot(n)) <= max_distance_px &&
             std::abs((foot - m.point).dot(n)) <= max_distance_px && t0 <= m.foot + max_gap_px &&
             t1 >= m.top - max_gap_px;
    };
    const auto host = std::find_if(merged.begin(), merged.end(), joins);
    if (host == merged.end()) {
      merged.push_back(e);
      continue;
    }
    host->top = std::min(host->top, (top - host->point).dot(host->down));
    host->foot = std::max(host->foot, (foot - host->point).dot(host->down));
  }
  return merged;
}

std::optional<VerticalEdge> RefineEdge(const Gradients& gradients, const VerticalEdge& edge,
                                       const EdgeRefinement& options) {
  const Eigen::Vector2d n = Normal(edge);
  const int search = static_cast<int>(std::ceil(options.search_px));
  std::vector<Peak> peaks;
  int samples = 0;
  for (double t = edge.top; t <= edge.foot; t += 1.0, ++samples) {
    if (auto peak = PeakAcross(gradients, edge.At(t), n, search)) peaks.push_back(*peak);
  }
  double polarity = 0.0;
  for (const Peak& p : peaks) polarity += p.strength;
  polarity = polarity >= 0 ? 1.0 : -1.0;
  std::vector<cv::Point2f> points;
  std::vector<double> strengths;
  for (const Peak& p : peaks) {
    if (p.strength * polarity <= 0) continue;
    points.emplace_back(static_cast<float>(p.point.x()), static_cast<float>(p.point.y()));
    strengths.push_back(std::abs(p.strength));
  }
  if (points.size() < 2 || 2 * static_cast<int>(points.size()) < samples) return std::nullopt;
  cv::Vec4f line;
  cv::fitLine(points, line, cv::DIST_HUBER, 0, 0.01, 0.01);
  VerticalEdge refined;
  refined.point = {line[2], line[3]};
  refined.down = Eigen::Vector2d(line[0], line[1]).normalized();
  if (refined.down.dot(edge.down) < 0) refined.down = -refined.down;
  refined.top = (edge.At(edge.top) - refined.point).dot(refined.down);
  refined.foot = (edge.At(edge.foot) - refined.point).dot(refined.down);
  std::nth_element(strengths.begin(), strengths.begin() + strengths.size() / 2, strengths.end());
  const double threshold = options.end_strength_fraction * strengths[strengths.size() / 2];
  const double start = std::max(refined.top, refined.foot - options.foot_search_px);
  refined.foot = FootAlong(gradients, refined, polarity, threshold, start, options);
  return refined;
}

}  // namespace fleetloc::mapmatch
