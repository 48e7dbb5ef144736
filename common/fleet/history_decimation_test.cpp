// DecimateMinMax keeps spikes and bounds the count.
#include "fleet/history_decimation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetloc::fleet {
namespace {

TEST(DecimateMinMax, ShortSeriesAreKeptWhole) {
  const std::vector<double> t = {0, 1, 2}, v = {5, 6, 7};
  EXPECT_EQ(DecimateMinMax(t, v, 10), (std::vector<size_t>{0, 1, 2}));
}

TEST(DecimateMinMax, OneHourAtOneHertzKeepsTheSpikeWithinFourHundredPoints) {
  std::vector<double> t, v;
  for (int i = 0; i < 3600; ++i) {
    t.push_back(1.7e9 + i);
    v.push_back(2.0 + 0.1 * std::sin(i * 0.01));  // cycle time around 2 ms
  }
  v[1234] = 80.0;  // one overrun
  v[2000] = 0.5;   // one dip
  const std::vector<size_t> kept = DecimateMinMax(t, v, 400);
  EXPECT_LE(kept.size(), 400u);
  EXPECT_GE(kept.size(), 390u);
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_NE(std::find(kept.begin(), kept.end(), 1234u), kept.end());
  EXPECT_NE(std::find(kept.begin(), kept.end(), 2000u), kept.end());
}

TEST(DecimateMinMax, GapsLeaveEmptyBucketsOut) {
  // Two bursts 1000 s apart: the buckets between them are empty and skipped.
  std::vector<double> t, v;
  for (int i = 0; i < 50; ++i) {
    t.push_back(i);
    v.push_back(i);
  }
  for (int i = 0; i < 50; ++i) {
    t.push_back(1000 + i);
    v.push_back(-i);
  }
  const std::vector<size_t> kept = DecimateMinMax(t, v, 20);
  ASSERT_FALSE(kept.empty());
  EXPECT_LE(kept.size(), 20u);
  EXPECT_EQ(kept.front(), 0u);
  EXPECT_EQ(kept.back(), 99u);  // the last bucket's minimum is the last sample
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
}

TEST(DecimateMinMax, FewerThanTwoPointsKeepsNothing) {
  const std::vector<double> t = {0, 1, 2}, v = {5, 6, 7};
  EXPECT_TRUE(DecimateMinMax(t, v, 1).empty());
}

}  // namespace
}  // namespace fleetloc::fleet
