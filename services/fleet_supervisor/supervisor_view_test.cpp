// The supervisor's JSON views: readiness (GET /readyz) from its checks.
#include "fleet_supervisor/supervisor_view.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet_supervisor {
namespace {

TEST(ReadinessJson, ReadyOnlyWhenEveryCheckHoldsAndTheFailingOneIsNamed) {
  bool ready = false;
  nlohmann::json out = ReadinessJson({{"dds", true, ""}, {"history", true, ""}}, &ready);
  EXPECT_TRUE(ready);
  EXPECT_EQ(out["ready"], true);
  out = ReadinessJson({{"dds", true, ""}, {"history", false, "h.db: the newest write failed"}},
                      &ready);
  EXPECT_FALSE(ready);
  EXPECT_EQ(out["ready"], false);
  EXPECT_EQ(out["checks"]["dds"]["ok"], true);
  EXPECT_EQ(out["checks"]["history"]["ok"], false);
  EXPECT_EQ(out["checks"]["history"]["detail"], "h.db: the newest write failed");
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
