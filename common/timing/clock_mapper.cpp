// Minimum-delay clock mapping over a sliding window (monotonic deque: O(1) amortized per sample).
#include "timing/clock_mapper.h"

#include <cmath>

namespace fleetloc::timing {

double ClockMapper::Map(double device_s, double host_arrival_s) {
  const double offset = host_arrival_s - device_s;
  if (!window_.empty() && std::abs(offset - window_.front().offset_s) > options_.reset_s) {
    window_.clear();  // the device clock restarted (or the host clock was stepped)
    ++resets_;
    samples_ = 0;
  }
  ++samples_;
  while (!window_.empty() && window_.back().offset_s >= offset) window_.pop_back();
  window_.push_back({host_arrival_s, offset});
  while (window_.front().host_s < host_arrival_s - options_.window_s) window_.pop_front();
  return device_s + window_.front().offset_s;
}

std::optional<double> ClockMapper::offset() const {
  if (window_.empty()) return std::nullopt;
  return window_.front().offset_s;
}

}  // namespace fleetloc::timing
