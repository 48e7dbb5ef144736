// Feature selection (paper 000 §2.6): template sites inside the overlap region, picked greedily to
// maximize texture score and spread, so that orientation is well conditioned.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/convex_polygon.h"

namespace fleetloc::tracking {

struct TemplateSite {
  Eigen::Vector2d center_px;  // frame continuous coordinates of the template centre
  double texture = 0.0;
};

// Grid sites (every step_px) whose square of half-size half_extent_px around the centre lies
// inside `region` (frame pixels), with texture ≥ min_texture. `texture_half` is the texture score
// of the frame at half resolution.
std::vector<TemplateSite> CandidateSites(const cv::Mat& texture_half,
                                         const geometry::ConvexPolygon& region, int step_px,
                                         double half_extent_px, double min_texture);

// Greedy selection: each pick maximizes texture × (1 − exp(−d² / 2σ²)), d being the distance to
// the nearest site already picked; sites closer than min_separation_px are never picked.
std::vector<TemplateSite> SelectSites(const std::vector<TemplateSite>& candidates, int max_sites,
                                      double spread_sigma_px, double min_separation_px);

}  // namespace fleetloc::tracking
