// Candidate sites and greedy texture-and-spread selection.
#include "tracking/feature_selection.h"

#include <cmath>
#include <limits>

namespace fleetloc::tracking {

std::vector<TemplateSite> CandidateSites(const cv::Mat& texture_half,
                                         const geometry::ConvexPolygon& region, int step_px,
                                         double half_extent_px, double min_texture) {
  std::vector<TemplateSite> sites;
  if (region.size() < 3) return sites;
  const double h = half_extent_px;
  for (int v = step_px; v < 2 * texture_half.rows; v += step_px) {
    for (int u = step_px; u < 2 * texture_half.cols; u += step_px) {
      const Eigen::Vector2d c(u, v);
      const float texture = texture_half.at<float>(v / 2, u / 2);
      if (texture < min_texture) continue;
      if (!geometry::Contains(region, c + Eigen::Vector2d(-h, -h)) ||
          !geometry::Contains(region, c + Eigen::Vector2d(h, -h)) ||
          !geometry::Contains(region, c + Eigen::Vector2d(h, h)) ||
          !geometry::Contains(region, c + Eigen::Vector2d(-h, h))) {
        continue;
      }
      sites.push_back({c, texture});
    }
  }
  return sites;
}

std::vector<TemplateSite> SelectSites(const std::vector<TemplateSite>& candidates, int max_sites,
                                      double spread_sigma_px, double min_separation_px) {
  std::vector<TemplateSite> chosen;
  // Squared distance from each candidate to its nearest chosen site.
  std::vector<double> nearest_sq(candidates.size(), std::numeric_limits<double>::infinity());
  const double two_sigma_sq = 2.0 * spread_sigma_px * spread_sigma_px;
  const double min_sep_sq = min_separation_px * min_separation_px;
  while (static_cast<int>(chosen.size()) < max_sites) {
    int best = -1;
    double best_score = 0.0;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (nearest_sq[i] < min_sep_sq) continue;
      const double spread = chosen.empty() ? 1.0 : 1.0 - std::exp(-nearest_sq[i] / two_sigma_sq);
      const double score = candidates[i].texture * spread;
      if (score > best_score) {
        best_score = score;
        best = static_cast<int>(i);
      }
    }
    if (best < 0) break;
    chosen.push_back(candidates[best]);
    for (size_t i = 0; i < candidates.size(); ++i) {
      nearest_sq[i] = std::min(nearest_sq[i],
                               (candidates[i].center_px - candidates[best].center_px).squaredNorm());
    }
  }
  return chosen;
}

}  // namespace fleetloc::tracking
