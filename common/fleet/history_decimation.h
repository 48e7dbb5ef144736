// Thinning a time series for a plot: at most `max_points` samples that keep its shape, spikes
// included (an operator looking for a cycle-time overrun must still see it after thinning).
#pragma once

#include <cstddef>
#include <vector>

namespace fleetloc::fleet {

// Indices (ascending) of the samples to keep from a series sorted by time `t`, with `value` the
// plotted quantity (same length). The time range is split into max_points / 2 equal buckets and
// each bucket keeps its minimum and its maximum sample (one if they coincide), so the result has
// at most max_points entries. All indices when the series is already short enough; none when
// max_points < 2 (requires t.size() == value.size(), checked).
std::vector<size_t> DecimateMinMax(const std::vector<double>& t, const std::vector<double>& value,
                                   size_t max_points);

}  // namespace fleetloc::fleet
