// Histogram: bucket placement, cumulative counts, sum, concurrent observers.
#include "metrics/histogram.h"

#include <gtest/gtest.h>

#include <limits>
#include <thread>
#include <vector>

namespace fleetloc::metrics {
namespace {

TEST(Histogram, CountsEachValueInTheFirstBucketAtOrAboveIt) {
  Histogram h({0.1, 1.0, 10.0});
  for (double v : {0.05, 0.1, 0.5, 3.0, 100.0}) h.Observe(v);
  const HistogramSnapshot s = h.Snapshot();
  ASSERT_EQ(s.cumulative.size(), 4u);
  EXPECT_EQ(s.cumulative[0], 2u);  // 0.05 and 0.1 (bounds are inclusive)
  EXPECT_EQ(s.cumulative[1], 3u);
  EXPECT_EQ(s.cumulative[2], 4u);
  EXPECT_EQ(s.cumulative[3], 5u);  // +Inf
  EXPECT_EQ(s.count, 5u);
  EXPECT_NEAR(s.sum, 103.65, 1e-9);
}

TEST(Histogram, IgnoresNaN) {
  Histogram h({1.0});
  h.Observe(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(h.Snapshot().count, 0u);
}

TEST(Histogram, ConcurrentObserversLoseNothing) {
  Histogram h(Histogram::LatencyBoundsS());
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&h] {
      for (int i = 0; i < 10000; ++i) h.Observe(0.003);
    });
  }
  for (std::thread& t : threads) t.join();
  const HistogramSnapshot s = h.Snapshot();
  EXPECT_EQ(s.count, 40000u);
  EXPECT_NEAR(s.sum, 120.0, 1e-6);
  EXPECT_EQ(s.cumulative[2], 0u);      // <= 2 ms
  EXPECT_EQ(s.cumulative[3], 40000u);  // <= 4 ms
}

TEST(HistogramDeathTest, RefusesBoundsOutOfOrder) {
  EXPECT_DEATH(Histogram({1.0, 0.5}), "ascending");
}

}  // namespace
}  // namespace fleetloc::metrics
