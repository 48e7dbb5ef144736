// StreamWatch: silence, NaN and time going backwards are each named, and clear after hold_s.
#include "timing/stream_watch.h"

#include <gtest/gtest.h>

namespace fleetloc::timing {
namespace {

TEST(StreamWatch, SilenceIsStaleUntilTheNextSample) {
  StreamWatch watch(0.5, 2.0);
  watch.Start(100.0);
  EXPECT_FALSE(watch.Stale(100.4));
  EXPECT_TRUE(watch.Stale(100.6));  // never a sample
  EXPECT_EQ(watch.Check(10.0, true, 100.7), SampleVerdict::kOk);
  EXPECT_FALSE(watch.Stale(101.1));
  EXPECT_TRUE(watch.Stale(101.3));
  EXPECT_EQ(watch.Check(10.1, true, 101.4), SampleVerdict::kOk);
  EXPECT_FALSE(watch.Stale(101.4));
}

TEST(StreamWatch, BackwardsAndNotFiniteSamplesAreNamedAndClearAfterTheHold) {
  StreamWatch watch(0.5, 2.0);
  EXPECT_EQ(watch.Check(10.0, true, 100.0), SampleVerdict::kOk);
  EXPECT_EQ(watch.Check(9.0, true, 100.1), SampleVerdict::kBackInTime);
  EXPECT_EQ(watch.Check(10.0, true, 100.2), SampleVerdict::kBackInTime);  // a repeat
  EXPECT_EQ(watch.Check(10.1, false, 100.3), SampleVerdict::kNotFinite);
  EXPECT_EQ(watch.Check(10.1, true, 100.4), SampleVerdict::kOk);
  EXPECT_EQ(*watch.last_good_t(), 10.1);
  EXPECT_EQ(watch.count(SampleVerdict::kBackInTime), 2);
  EXPECT_EQ(watch.count(SampleVerdict::kNotFinite), 1);
  EXPECT_TRUE(watch.Recent(SampleVerdict::kBackInTime, 102.1));
  EXPECT_FALSE(watch.Recent(SampleVerdict::kBackInTime, 102.3));
  EXPECT_TRUE(watch.Recent(SampleVerdict::kNotFinite, 102.3));
  EXPECT_FALSE(watch.Recent(SampleVerdict::kNotFinite, 102.4));
}

TEST(CountWatch, ACountThatRoseIsNamedForTheHoldThenClearsUntilItRisesAgain) {
  CountWatch watch(2.0);
  EXPECT_FALSE(watch.Recent(0, 100.0));  // nothing yet
  EXPECT_TRUE(watch.Recent(1, 100.5));   // one packet lost
  EXPECT_TRUE(watch.Recent(1, 102.5));   // held
  EXPECT_FALSE(watch.Recent(1, 102.6));  // cleared: the same count since 100.5
  EXPECT_TRUE(watch.Recent(3, 110.0));   // risen again
  EXPECT_FALSE(watch.Recent(3, 112.1));
  EXPECT_FALSE(watch.Recent(0, 113.0));  // its source restarted: the new base, not a rise
  EXPECT_TRUE(watch.Recent(1, 113.1));
}

}  // namespace
}  // namespace fleetloc::timing
