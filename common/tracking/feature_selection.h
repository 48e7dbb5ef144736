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

// Where a site may lie: the square of half-size half_extent_px around its centre must be inside
// `region` (frame pixels, convex).
struct SiteBounds {
  geometry::ConvexPolygon region;
  double half_extent_px = 0.0;
};

// Grid sites inside every one of `bounds`, with texture ≥ min_texture; at most max_sites, the best
// textured. `texture_grid` element (r, c) scores frame point ((c + 1)·step_px, (r + 1)·step_px).
std::vector<TemplateSite> CandidateSites(const cv::Mat& texture_grid, int step_px,
                                         const std::vector<SiteBounds>& bounds, double min_texture,
                                         size_t max_sites = 600);

// The texture a candidate needs on this frame: `relative` × the frame's `quantile` texture (so a
// plain floor keeps its best sites and a rich one only its strong ones), at least `floor`.
double RelativeTextureThreshold(const cv::Mat& texture_grid, double quantile, double relative,
                                double floor);

// Every candidate's texture capped at the candidates' `quantile` texture (0 < quantile < 1; else
// unchanged), so that above it the spread alone decides: the strongest texture of a frame is
// often an occluder the mosaic does not have (debris, a tyre mark's edge), not the floor.
void CapTexture(double quantile, std::vector<TemplateSite>* candidates);

// Greedy selection: each pick maximizes texture × d² / (d² + 2σ²), d being the distance to
// the nearest site already picked; sites closer than min_separation_px are never picked.
std::vector<TemplateSite> SelectSites(const std::vector<TemplateSite>& candidates, int max_sites,
                                      double spread_sigma_px, double min_separation_px);

}  // namespace fleetloc::tracking
