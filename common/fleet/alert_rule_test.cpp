// HysteresisAlarm against hand-worked sequences.
#include "fleet/alert_rule.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet {
namespace {

using Change = HysteresisAlarm::Change;

TEST(HysteresisAlarm, RaisesOnlyAfterTheHoldAndClearsBelowTheLowerThreshold) {
  HysteresisAlarm alarm({/*raise_above=*/50.0, /*clear_below=*/35.0, /*raise_after_s=*/2.0,
                         /*clear_after_s=*/3.0});
  EXPECT_EQ(alarm.Update(0.0, 60.0), Change::kNone);  // above since t=0
  EXPECT_EQ(alarm.Update(1.9, 61.0), Change::kNone);
  EXPECT_EQ(alarm.Update(2.0, 55.0), Change::kRaised);
  EXPECT_TRUE(alarm.active());
  // 40 is below the raise threshold but not below the clear threshold: stays raised.
  EXPECT_EQ(alarm.Update(3.0, 40.0), Change::kNone);
  EXPECT_EQ(alarm.Update(10.0, 40.0), Change::kNone);
  EXPECT_EQ(alarm.Update(11.0, 30.0), Change::kNone);
  EXPECT_EQ(alarm.Update(13.9, 30.0), Change::kNone);
  EXPECT_EQ(alarm.Update(14.0, 30.0), Change::kCleared);
  EXPECT_FALSE(alarm.active());
}

TEST(HysteresisAlarm, ABriefSpikeDoesNotRaise) {
  HysteresisAlarm alarm({50.0, 35.0, 2.0, 0.0});
  EXPECT_EQ(alarm.Update(0.0, 80.0), Change::kNone);
  EXPECT_EQ(alarm.Update(1.5, 20.0), Change::kNone);  // back under: the hold restarts
  EXPECT_EQ(alarm.Update(2.5, 80.0), Change::kNone);
  EXPECT_EQ(alarm.Update(4.0, 80.0), Change::kNone);
  EXPECT_EQ(alarm.Update(4.5, 80.0), Change::kRaised);
}

TEST(HysteresisAlarm, ZeroHoldsActAtOnce) {
  HysteresisAlarm alarm({0.5, 0.5, 0.0, 0.0});
  EXPECT_EQ(alarm.Update(0.0, 1.0), Change::kRaised);
  EXPECT_EQ(alarm.Update(0.1, 1.0), Change::kNone);
  EXPECT_EQ(alarm.Update(0.2, 0.0), Change::kCleared);
}

TEST(HysteresisOptions, InvertedThresholdsAreRejected) {
  EXPECT_FALSE(Validate({1.0, 2.0, 0, 0}, "cycle").ok());
  EXPECT_FALSE(Validate({2.0, 1.0, -1, 0}, "cycle").ok());
  EXPECT_TRUE(Validate({2.0, 1.0, 0, 5}, "cycle").ok());
}

}  // namespace
}  // namespace fleetloc::fleet
