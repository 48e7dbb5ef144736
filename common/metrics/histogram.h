// A fixed-bucket histogram of durations (or any non-negative value) that any thread may feed and
// any thread may read: constant memory, lock-free Observe, cumulative counts like Prometheus's.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace fleetloc::metrics {

struct HistogramSnapshot {
  std::vector<double> upper_bounds;       // ascending; +Inf is implied after the last
  std::vector<std::uint64_t> cumulative;  // one per bound, then one for +Inf (== count)
  double sum = 0.0;
  std::uint64_t count = 0;
};

class Histogram {
 public:
  // `upper_bounds` must be finite and strictly ascending (checked: aborts otherwise).
  explicit Histogram(std::vector<double> upper_bounds);

  // Counts `value` in the first bucket whose bound is >= value (NaN is ignored).
  void Observe(double value);
  HistogramSnapshot Snapshot() const;

  // 0.5 ms .. 2 s, roughly doubling: a tracker cycle, a tile round trip.
  static std::vector<double> LatencyBoundsS();

 private:
  std::vector<double> bounds_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> counts_;  // per bucket (not cumulative), +Inf last
  std::atomic<std::uint64_t> count_{0};
  std::atomic<double> sum_{0.0};
};

}  // namespace fleetloc::metrics
