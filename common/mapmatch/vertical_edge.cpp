// Near-vertical edges: selection, merging, line fits and the sub-pixel foot (see vertical_edge.h).
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

constexpr double kPersistPx = 2.0;      // a fade lasts this long (noise dips do not)
constexpr double kLastStretchPx = 8.0;  // the stretch above the fade that sets the local contrast
constexpr double kBlurMarginPx = 2.5;   // ... leaving out the blurred end itself
constexpr double kKinkPx = 0.75;        // a boundary this far off the line has left it
constexpr double kKinkRunPx = 6.0;      // ... and keeps leaving over this run
constexpr int kKinkSearchPx = 4;

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

Eigen::Vector2d Normal(const EdgeSegment& edge) {
  return {-edge.direction.y(), edge.direction.x()};
}

// The edge's strength at t: the polarity-signed gradient across its line.
double StrengthAt(const Gradients& g, const EdgeSegment& edge, double t, double polarity) {
  return polarity * Across(g, edge.At(t), Normal(edge));
}

// Where the strength falls below `threshold` for good (for `persist_px`) scanning down from
// `start`, interpolated between the last strong and the first weak sample; when the edge is already
// weak at `start`, where it becomes strong scanning up.
double FirstDrop(const Gradients& g, const EdgeSegment& edge, double polarity, double threshold,
                 double start, double persist_px, double step) {
  const auto strength = [&](double t) { return StrengthAt(g, edge, t, polarity); };
  double t = start, s = strength(t);
  if (s < threshold) {  // scan up to the edge
    while (t > edge.begin && s < threshold) {
      t -= step;
      s = strength(t);
    }
    return t;
  }
  const int persist = std::max(1, static_cast<int>(std::ceil(persist_px / step)));
  while (s > 0.0) {  // 0 outside the image
    const double next = strength(t + step);
    if (next < threshold) {
      int weak = 1;
      while (weak < persist && strength(t + (weak + 1) * step) < threshold) ++weak;
      if (weak == persist) return t + step * (s - threshold) / (s - next);
    }
    t += step;
    s = next;
  }
  return t;
}

// The median strength over [from, to].
double MedianStrength(const Gradients& g, const EdgeSegment& edge, double polarity, double from,
                      double to, double step) {
  std::vector<double> values;
  for (double t = from; t <= to; t += step) values.push_back(StrengthAt(g, edge, t, polarity));
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// Where the edge bends away from its line before fading: below a corner seen at a grazing angle
// the floor boundary continues almost along the edge. Scanning down from `start`, the gradient
// peak's lateral offset from the line leaves ±kKinkPx for good and keeps growing; the bend is
// extrapolated back to zero offset. nullopt when the edge stays on its line up to `until`.
std::optional<double> BendAlong(const Gradients& g, const EdgeSegment& edge, double polarity,
                                double start, double until) {
  const Eigen::Vector2d n = Normal(edge);
  const auto offset = [&](double t) -> std::optional<double> {
    const std::optional<Peak> peak = PeakAcross(g, edge.At(t), n, kKinkSearchPx);
    if (!peak || peak->strength * polarity <= 0) return std::nullopt;
    return (peak->point - edge.At(t)).dot(n);
  };
  for (double t = start; t <= until; t += 0.5) {
    const std::optional<double> o0 = offset(t), o1 = offset(t + kKinkRunPx / 2),
                                o2 = offset(t + kKinkRunPx);
    if (!o0 || !o1 || !o2 || std::abs(*o0) < kKinkPx) continue;
    const double sign = *o0 > 0 ? 1.0 : -1.0;
    // Growing steadily in the same direction: a boundary leaving the line.
    const double first = sign * (*o1 - *o0), second = sign * (*o2 - *o1);
    if (first <= 0 || second <= 0 || std::max(first, second) > 2 * std::min(first, second)) {
      continue;  // a straight boundary leaves the line at a steady rate
    }
    const double slope = (*o2 - *o0) / kKinkRunPx;
    return std::max(start, t - *o0 / slope);
  }
  return std::nullopt;
}

// Where the edge ends: first where it fades below fade_fraction × its median strength (its
// contrast may change along the way, e.g. a silhouette against a changing background), then the
// half-maximum of its last stretch's strength (the blurred end of a step is crossed at half height
// where the step ends).
double EdgeEnd(const Gradients& g, const EdgeSegment& edge, double polarity, double median_strength,
               const EdgeRefinement& options) {
  const double step = options.step_px;
  const double start = std::max(edge.begin, edge.end - options.foot_search_px);
  const double fade = FirstDrop(g, edge, polarity, options.fade_fraction * median_strength, start,
                                kPersistPx, step);
  const double from = std::max(edge.begin, fade - kLastStretchPx);
  if (fade - from < 1.0) return fade;
  const double local = MedianStrength(g, edge, polarity, from, fade - kBlurMarginPx, step);
  const double end =
      FirstDrop(g, edge, polarity, options.end_strength_fraction * local, from, step, step);
  const double faded = std::clamp(end, from, fade);
  const std::optional<double> bend =
      BendAlong(g, edge, polarity, std::max(start, faded - 2 * kLastStretchPx), faded);
  return bend ? std::min(*bend, faded) : faded;
}

struct EdgeFit {
  EdgeSegment line;
  double polarity = 1.0;         // sign of the gradient across the line
  double median_strength = 0.0;  // of the peaks along it
};

// The gradient peaks across the segment every pixel along it, the dominant polarity's peaks
// fitted with a robust line; nullopt when fewer than half the samples give such a peak.
std::optional<EdgeFit> FitWithStrength(const Gradients& g, const EdgeSegment& segment,
                                       double search_px) {
  const Eigen::Vector2d n = Normal(segment);
  const int search = static_cast<int>(std::ceil(search_px));
  std::vector<Peak> peaks;
  int samples = 0;
  for (double t = segment.begin; t <= segment.end; t += 1.0, ++samples) {
    if (auto peak = PeakAcross(g, segment.At(t), n, search)) peaks.push_back(*peak);
  }
  double balance = 0.0;
  for (const Peak& p : peaks) balance += p.strength;
  EdgeFit fit;
  fit.polarity = balance >= 0 ? 1.0 : -1.0;
  std::vector<cv::Point2f> points;
  std::vector<double> strengths;
  for (const Peak& p : peaks) {
    if (p.strength * fit.polarity <= 0) continue;
    points.emplace_back(static_cast<float>(p.point.x()), static_cast<float>(p.point.y()));
    strengths.push_back(std::abs(p.strength));
  }
  if (points.size() < 2 || 2 * static_cast<int>(points.size()) < samples) return std::nullopt;
  cv::Vec4f line;
  cv::fitLine(points, line, cv::DIST_HUBER, 0, 0.01, 0.01);
  fit.line.point = {line[2], line[3]};
  fit.line.direction = Eigen::Vector2d(line[0], line[1]).normalized();
  if (fit.line.direction.dot(segment.direction) < 0) fit.line.direction *= -1;
  fit.line.begin = (segment.At(segment.begin) - fit.line.point).dot(fit.line.direction);
  fit.line.end = (segment.At(segment.end) - fit.line.point).dot(fit.line.direction);
  std::nth_element(strengths.begin(), strengths.begin() + strengths.size() / 2, strengths.end());
  fit.median_strength = strengths[strengths.size() / 2];
  return fit;
}

// Where the edge's line crosses a boundary line within snap_distance_px of its current end, the
// boundary segment reaching within snap_reach_px of the crossing; the nearest such crossing.
std::optional<double> NearestBoundaryCrossing(const EdgeSegment& edge,
                                              const std::vector<EdgeSegment>& boundaries,
                                              const EdgeRefinement& options) {
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  std::optional<double> best;
  for (const EdgeSegment& b : boundaries) {
    const double denominator = cross(edge.direction, b.direction);
    if (std::abs(denominator) < 1e-6) continue;
    const Eigen::Vector2d offset = b.point - edge.point;
    const double t = cross(offset, b.direction) / denominator;
    const double s = cross(offset, edge.direction) / denominator;
    if (std::abs(t - edge.end) > options.snap_distance_px || t <= edge.begin) continue;
    if (s < b.begin - options.snap_reach_px || s > b.end + options.snap_reach_px) continue;
    if (!best || std::abs(t - edge.end) < std::abs(*best - edge.end)) best = t;
  }
  return best;
}

}  // namespace

Eigen::Vector2d DownDirectionAt(const Eigen::Vector3d& nadir_vp, const Eigen::Vector2d& pixel) {
  // d/ds of the image of X + s·down is proportional to vp.xy - vp.z · pixel (positive depth).
  return (nadir_vp.head<2>() - nadir_vp.z() * pixel).normalized();
}

SortedSegments SortSegments(const std::vector<cv::Vec4i>& segments, const Eigen::Vector3d& nadir_vp,
                            double max_vertical_deviation_rad, double min_boundary_angle_rad) {
  SortedSegments sorted;
  for (const cv::Vec4i& s : segments) {
    const Eigen::Vector2d a(s[0], s[1]), b(s[2], s[3]);
    const double length = (b - a).norm();
    if (length == 0.0) continue;
    const Eigen::Vector2d mid = (a + b) / 2;
    const Eigen::Vector2d down = DownDirectionAt(nadir_vp, mid);
    Eigen::Vector2d along = (b - a) / length;
    if (along.dot(down) < 0) along = -along;
    const double angle = std::acos(std::min(1.0, along.dot(down)));
    const EdgeSegment segment{mid, along, -length / 2, length / 2};
    if (angle <= max_vertical_deviation_rad) sorted.vertical.push_back(segment);
    if (angle >= min_boundary_angle_rad) sorted.boundaries.push_back(segment);
  }
  return sorted;
}

std::vector<EdgeSegment> MergeCollinear(std::vector<EdgeSegment> edges, double max_distance_px,
                                        double max_gap_px) {
  std::sort(edges.begin(), edges.end(),
            [](const EdgeSegment& a, const EdgeSegment& b) { return a.Length() > b.Length(); });
  std::vector<EdgeSegment> merged;
  for (const EdgeSegment& e : edges) {
    const Eigen::Vector2d top = e.At(e.begin), foot = e.At(e.end);
    const auto joins = [&](const EdgeSegment& m) {
      const Eigen::Vector2d n = Normal(m);
      const double t0 = (top - m.point).dot(m.direction), t1 = (foot - m.point).dot(m.direction);
      return std::abs((top - m.point).dot(n)) <= max_distance_px &&
             std::abs((foot - m.point).dot(n)) <= max_distance_px && t0 <= m.end + max_gap_px &&
             t1 >= m.begin - max_gap_px;
    };
    const auto host = std::find_if(merged.begin(), merged.end(), joins);
    if (host == merged.end()) {
      merged.push_back(e);
      continue;
    }
    host->begin = std::min(host->begin, (top - host->point).dot(host->direction));
    host->end = std::max(host->end, (foot - host->point).dot(host->direction));
  }
  return merged;
}

std::optional<EdgeSegment> FitEdgeLine(const Gradients& gradients, const EdgeSegment& segment,
                                       double search_px) {
  std::optional<EdgeFit> fit = FitWithStrength(gradients, segment, search_px);
  if (!fit) return std::nullopt;
  return fit->line;
}

std::optional<EdgeSegment> RefineEdge(const Gradients& gradients, const EdgeSegment& edge,
                                      const std::vector<EdgeSegment>& boundaries,
                                      const EdgeRefinement& options) {
  std::optional<EdgeFit> fit = FitWithStrength(gradients, edge, options.search_px);
  if (!fit) return std::nullopt;
  EdgeSegment refined = fit->line;
  refined.end = EdgeEnd(gradients, refined, fit->polarity, fit->median_strength, options);
  if (auto crossing = NearestBoundaryCrossing(refined, boundaries, options))
    refined.end = *crossing;
  return refined;
}

}  // namespace fleetloc::mapmatch
