// Vehicle reputation: a vehicle is quarantined when most of its recent patches fail, not for a
// few failures among good ones, and a release forgets the recent record.
#include "mapping/vehicle_reputation.h"

#include <gtest/gtest.h>

namespace fleetloc::mapping {
namespace {

TEST(VehicleReputation, AVehicleWhosePatchesKeepFailingIsQuarantinedOnce) {
  VehicleStanding s;
  const ReputationOptions o;  // window 16, at least 6 judged, quarantine above 75 % refused
  int quarantined_at = -1;
  for (int i = 0; i < 10; ++i) {
    if (RecordVerdict(&s, false, "unregistered", o)) {
      EXPECT_EQ(quarantined_at, -1);
      quarantined_at = i;
    }
  }
  EXPECT_EQ(quarantined_at, 5);  // the sixth refusal: the first verdict that may quarantine
  EXPECT_TRUE(s.quarantined);
  EXPECT_EQ(s.refused, 10);
  EXPECT_NE(s.reason.find("unregistered"), std::string::npos) << s.reason;
  EXPECT_EQ(s.recent.size(), 10u);
}

TEST(VehicleReputation, OccasionalFailuresAmongGoodPatchesAreTolerated) {
  VehicleStanding s;
  const ReputationOptions o;
  for (int i = 0; i < 200; ++i) {
    EXPECT_FALSE(RecordVerdict(&s, i % 3 != 0, i % 3 == 0 ? "no_anchor" : "", o)) << i;
  }
  EXPECT_FALSE(s.quarantined);
  EXPECT_EQ(s.recent.size(), 16u);  // the window
  EXPECT_EQ(s.admitted + s.refused, 200);
}

TEST(VehicleReputation, ReleaseForgetsTheRecentVerdictsButNotTheTotals) {
  VehicleStanding s;
  const ReputationOptions o;
  for (int i = 0; i < 8; ++i) RecordVerdict(&s, false, "flat", o);
  ASSERT_TRUE(s.quarantined);
  Release(&s);
  EXPECT_FALSE(s.quarantined);
  EXPECT_TRUE(s.recent.empty());
  EXPECT_EQ(s.refused, 8);
  // It must fail six times again before it is quarantined again.
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(RecordVerdict(&s, false, "flat", o));
  EXPECT_TRUE(RecordVerdict(&s, false, "flat", o));
}

TEST(VehicleReputation, OptionsAreRangeChecked) {
  EXPECT_EQ(OptionsProblem(ReputationOptions{}), "");
  EXPECT_NE(OptionsProblem(ReputationOptions{4, 6, 0.5}).find("min_judged"), std::string::npos);
  EXPECT_NE(OptionsProblem(ReputationOptions{16, 6, 1.0}).find("max_refused_fraction"),
            std::string::npos);
}

}  // namespace
}  // namespace fleetloc::mapping
