// Dense spots: densest points first, each climbed to its density mode by mean shift (see
// dense_spots.h).
#include "mapmatch/dense_spots.h"

#include <algorithm>
#include <numeric>

#include "base/status.h"
#include "mapmatch/mean_shift.h"

namespace fleetloc::mapmatch {
namespace {

double WeightOf(std::span<const double> weights, std::size_t i) {
  return weights.empty() ? 1.0 : weights[i];
}

// The summed weight of the points within `radius` of each point (itself included). Points sorted
// by x, so each one only looks at the strip |dx| < radius: O(n log n + n × strip).
std::vector<double> Densities(std::span<const Eigen::Vector2d> points,
                              std::span<const double> weights, double radius) {
  std::vector<std::size_t> by_x(points.size());
  std::iota(by_x.begin(), by_x.end(), 0);
  std::sort(by_x.begin(), by_x.end(),
            [&](std::size_t a, std::size_t b) { return points[a].x() < points[b].x(); });
  std::vector<double> density(points.size(), 0.0);
  const double r2 = radius * radius;
  std::size_t first = 0;  // the first point of the strip of the current one
  for (std::size_t k = 0; k < by_x.size(); ++k) {
    const Eigen::Vector2d& p = points[by_x[k]];
    while (points[by_x[first]].x() <= p.x() - radius) ++first;
    for (std::size_t n = first; n < by_x.size() && points[by_x[n]].x() < p.x() + radius; ++n) {
      if ((points[by_x[n]] - p).squaredNorm() < r2) density[by_x[k]] += WeightOf(weights, by_x[n]);
    }
  }
  return density;
}

bool Covered(const std::vector<DenseSpot>& spots, const Eigen::Vector2d& xy, double radius) {
  return std::any_of(spots.begin(), spots.end(), [&](const DenseSpot& s) {
    return (s.center - xy).squaredNorm() < radius * radius;
  });
}

}  // namespace

std::vector<DenseSpot> FindDenseSpots(std::span<const Eigen::Vector2d> points,
                                      std::span<const double> weights, double radius_m,
                                      int max_spots) {
  FLEETLOC_CHECK(radius_m > 0.0 && max_spots >= 0);
  FLEETLOC_CHECK(weights.empty() || weights.size() == points.size());
  const std::vector<double> density = Densities(points, weights, radius_m);
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return density[a] > density[b]; });
  std::vector<DenseSpot> spots;
  // Starts that climb to a known spot cost a mean shift each; a few per spot are plenty.
  int climbs_left = 4 * max_spots;
  for (const std::size_t i : order) {
    if (static_cast<int>(spots.size()) >= max_spots || climbs_left-- <= 0) break;
    if (WeightOf(weights, i) <= 0.0 || Covered(spots, points[i], radius_m)) continue;
    const Result<MeanShiftResult> mode =
        MeanShiftMode(points, weights, points[i], MeanShiftOptions{.radius = radius_m});
    FLEETLOC_CHECK(mode.ok());  // inputs checked above; a start on a point always has a window
    if (Covered(spots, mode->mode, radius_m)) continue;
    spots.push_back({mode->mode, mode->support_weight});
  }
  std::stable_sort(spots.begin(), spots.end(),
                   [](const DenseSpot& a, const DenseSpot& b) { return a.support > b.support; });
  return spots;
}

}  // namespace fleetloc::mapmatch
