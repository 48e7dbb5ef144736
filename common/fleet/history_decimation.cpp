// Min/max bucket decimation.
#include "fleet/history_decimation.h"

#include <algorithm>
#include <numeric>

#include "base/status.h"

namespace fleetloc::fleet {

std::vector<size_t> DecimateMinMax(const std::vector<double>& t, const std::vector<double>& value,
                                   size_t max_points) {
  FLEETLOC_CHECK(t.size() == value.size());
  std::vector<size_t> kept;
  if (t.size() <= max_points) {
    kept.resize(t.size());
    std::iota(kept.begin(), kept.end(), size_t{0});
    return kept;
  }
  const size_t buckets = max_points / 2;
  if (buckets == 0) return kept;
  const double t0 = t.front();
  const double span = std::max(t.back() - t0, 1e-12);
  size_t i = 0;
  for (size_t b = 0; b < buckets && i < t.size(); ++b) {
    const double end = t0 + span * static_cast<double>(b + 1) / static_cast<double>(buckets);
    size_t lo = i, hi = i;
    for (; i < t.size() && (t[i] <= end || b + 1 == buckets); ++i) {
      if (value[i] < value[lo]) lo = i;
      if (value[i] > value[hi]) hi = i;
    }
    if (i == lo && i == hi) continue;  // empty bucket (lo/hi still point past it)
    kept.push_back(std::min(lo, hi));
    if (lo != hi) kept.push_back(std::max(lo, hi));
  }
  return kept;
}

}  // namespace fleetloc::fleet
