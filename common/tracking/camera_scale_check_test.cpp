// CheckCameraResolution: within the tolerance accepted, beyond it refused with both values.
#include "tracking/camera_scale_check.h"

#include <gtest/gtest.h>

namespace fleetloc::tracking {
namespace {

TEST(CheckCameraResolution, WithinFivePercentIsAccepted) {
  EXPECT_TRUE(CheckCameraResolution(0.0005, 0.0005, "camera.json").ok());
  EXPECT_TRUE(CheckCameraResolution(0.000524, 0.0005, "camera.json").ok());
  EXPECT_TRUE(CheckCameraResolution(0.000476, 0.0005, "camera.json").ok());
}

TEST(CheckCameraResolution, TwiceTheMosaicsIsRefusedWithBothValues) {
  const Status s = CheckCameraResolution(0.001, 0.0005, "run/camera.json");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.ExitCode(), 2);
  EXPECT_NE(s.message().find("run/camera.json"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("0.001 m/px"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("0.0005 m/px"), std::string::npos) << s.message();
  EXPECT_FALSE(CheckCameraResolution(0.00053, 0.0005, "c").ok());  // 6 %
  EXPECT_FALSE(CheckCameraResolution(0.0005, 0.0, "c").ok());
}

}  // namespace
}  // namespace fleetloc::tracking
