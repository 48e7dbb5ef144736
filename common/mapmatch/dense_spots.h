// Dense spots among measured points: the modes of the points' density found by mean shift
// (mean_shift.h) started from the densest points. A landmark seen several times leaves a tight
// cluster of points, so its spot stands out of uniform outliers; clutter that looks like a
// landmark (a shelf leg) leaves a spot too — telling them apart is the map fit's job. The robust
// map fit (robust_map_fit.h) pairs spots with landmarks to vote for starting corrections.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

namespace fleetloc::mapmatch {

struct DenseSpot {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // the mean-shift mode
  double support = 0.0;  // summed weight of the points within the radius of the center
};

// At most `max_spots` spots, densest first, no two closer than `radius_m`. Each is the mode of a
// mean shift of radius `radius_m` started from a point no spot found so far covers, the points
// taken densest first (ties in input order). `weights` may be empty (all 1); otherwise one finite
// weight >= 0 per point (points of weight 0 are skipped). Requires finite points, radius_m > 0
// and max_spots >= 0 (checked: aborts otherwise — the caller validates its input).
std::vector<DenseSpot> FindDenseSpots(std::span<const Eigen::Vector2d> points,
                                      std::span<const double> weights, double radius_m,
                                      int max_spots);

}  // namespace fleetloc::mapmatch
