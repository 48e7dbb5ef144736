// The percentile of a sample (nearest rank), for the summaries and benchmarks every layer prints:
// the agent's cycle and latency statistics, the replay's accuracy, fleetctl's benchmarks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace fleetloc {

// The value of rank ceil(percent / 100 · n) (1-based, clamped to 1..n) of `values`; `percent` in
// 0..100, so 50 is the median. 0 for an empty sample.
inline double Percentile(std::vector<double> values, double percent) {
  if (values.empty()) return 0.0;
  const double rank = std::ceil(percent / 100.0 * static_cast<double>(values.size())) - 1.0;
  const size_t k = static_cast<size_t>(std::clamp(rank, 0.0, values.size() - 1.0));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace fleetloc
