// Candidate sites and greedy texture-and-spread selection.
#include "tracking/feature_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetloc::tracking {

namespace {

// True if the square of half-size h around c lies inside the counter-clockwise convex polygon:
// for each edge a→b, the square's worst corner must be on the left, i.e.
// cross(b − a, c − a) ≥ h·(|b.x − a.x| + |b.y − a.y|).
bool SquareInside(const geometry::ConvexPolygon& ccw, const Eigen::Vector2d& c, double h) {
  for (size_t i = 0; i < ccw.size(); ++i) {
    const Eigen::Vector2d& a = ccw[i];
    const Eigen::Vector2d e = ccw[(i + 1) % ccw.size()] - a;
    const double cross = e.x() * (c.y() - a.y()) - e.y() * (c.x() - a.x());
    if (cross < h * (std::abs(e.x()) + std::abs(e.y()))) return false;
  }
  return true;
}

}  // namespace

std::vector<TemplateSite> CandidateSites(const cv::Mat& texture_grid, int step_px,
                                         const std::vector<SiteBounds>& bounds, double min_texture,
                                         size_t max_sites) {
  std::vector<TemplateSite> sites;
  std::vector<SiteBounds> ccw;
  for (const SiteBounds& b : bounds) {
    if (b.region.size() < 3) return sites;
    ccw.push_back({geometry::CounterClockwise(b.region), b.half_extent_px});
  }
  const auto inside = [&ccw](const Eigen::Vector2d& center) {
    return std::all_of(ccw.begin(), ccw.end(), [&center](const SiteBounds& b) {
      return SquareInside(b.region, center, b.half_extent_px);
    });
  };
  for (int r = 0; r < texture_grid.rows; ++r) {
    for (int c = 0; c < texture_grid.cols; ++c) {
      const float texture = texture_grid.at<float>(r, c);
      if (texture < min_texture) continue;
      const Eigen::Vector2d center((c + 1.0) * step_px, (r + 1.0) * step_px);
      if (inside(center)) sites.push_back({center, texture});
    }
  }
  if (sites.size() > max_sites) {
    std::nth_element(
        sites.begin(), sites.begin() + max_sites, sites.end(),
        [](const TemplateSite& a, const TemplateSite& b) { return a.texture > b.texture; });
    sites.resize(max_sites);
  }
  return sites;
}

double RelativeTextureThreshold(const cv::Mat& texture_grid, double quantile, double relative,
                                double floor) {
  if (relative <= 0.0) return floor;
  std::vector<float> scores;
  scores.reserve(texture_grid.total());
  for (int r = 0; r < texture_grid.rows; ++r) {
    const float* row = texture_grid.ptr<float>(r);
    for (int c = 0; c < texture_grid.cols; ++c) {
      if (row[c] > 0.0f) scores.push_back(row[c]);  // 0: the window left the image
    }
  }
  if (scores.empty()) return floor;
  const auto at = scores.begin() + static_cast<long>(quantile * (scores.size() - 1));
  std::nth_element(scores.begin(), at, scores.end());
  return std::max(floor, relative * *at);
}

void CapTexture(double quantile, std::vector<TemplateSite>* candidates) {
  if (candidates->empty() || !(quantile > 0 && quantile < 1)) return;
  std::vector<double> textures;
  textures.reserve(candidates->size());
  for (const TemplateSite& site : *candidates) textures.push_back(site.texture);
  const auto at = textures.begin() + static_cast<long>(quantile * (textures.size() - 1));
  std::nth_element(textures.begin(), at, textures.end());
  for (TemplateSite& site : *candidates) site.texture = std::min(site.texture, *at);
}

std::vector<TemplateSite> SelectSites(const std::vector<TemplateSite>& candidates, int max_sites,
                                      double spread_sigma_px, double min_separation_px) {
  std::vector<TemplateSite> chosen;
  // Squared distance from each candidate to its nearest chosen site.
  std::vector<double> nearest_sq(candidates.size(), std::numeric_limits<double>::infinity());
  const double two_sigma_sq = 2.0 * spread_sigma_px * spread_sigma_px;
  // Spread factor d² / (d² + 2σ²): the same saturating shape as 1 − exp(−d²/2σ²) without an
  // exp per candidate and pick.
  const double min_sep_sq = min_separation_px * min_separation_px;
  while (static_cast<int>(chosen.size()) < max_sites) {
    int best = -1;
    double best_score = 0.0;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (nearest_sq[i] < min_sep_sq) continue;
      const double spread = chosen.empty() ? 1.0 : nearest_sq[i] / (nearest_sq[i] + two_sigma_sq);
      const double score = candidates[i].texture * spread;
      if (score > best_score) {
        best_score = score;
        best = static_cast<int>(i);
      }
    }
    if (best < 0) break;
    chosen.push_back(candidates[best]);
    for (size_t i = 0; i < candidates.size(); ++i) {
      nearest_sq[i] = std::min(
          nearest_sq[i], (candidates[i].center_px - candidates[best].center_px).squaredNorm());
    }
  }
  return chosen;
}

}  // namespace fleetloc::tracking
