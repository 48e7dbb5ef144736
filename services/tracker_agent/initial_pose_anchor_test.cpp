// AnchorInitialPose: a start pose is anchored at its stamp when odometry covers it, at the newest
// sample when its stamp is zero or ahead, and refused when its stamp is older than the history
// (the agent joined late and the vehicle drove on: anchoring it at the newest sample placed the
// vehicle up to a metre from where it was, the first frames could not track, lock was lost).
#include "tracker_agent/initial_pose_anchor.h"

#include <gtest/gtest.h>

namespace fleetloc::tracker_agent {
namespace {

tracking::OdometryHistory History(double from, double to) {
  tracking::OdometryHistory h(10.0, 0.02);
  for (double t = from; t <= to + 1e-9; t += 0.01)
    EXPECT_TRUE(h.Add({t, {t * 0.5, 0.0, 0.0}}).ok());
  return h;
}

TEST(InitialPoseAnchorTest, AStampOlderThanTheOdometryHistoryIsRefused) {
  // The bench's late-joining agent: start pose stamped 340.1 (standing), odometry from 343.8.
  const tracking::OdometryHistory h = History(343.8, 343.88);
  const InitialPoseAnchor a = AnchorInitialPose(340.1, h, 343.88);
  EXPECT_FALSE(a.ok);
  EXPECT_NE(a.reason.find("before the odometry history"), std::string::npos) << a.reason;
}

TEST(InitialPoseAnchorTest, ACoveredStampIsAnchoredThereZeroOrFutureAtTheNewestSample) {
  const tracking::OdometryHistory h = History(340.0, 341.0);
  EXPECT_TRUE(AnchorInitialPose(340.1, h, 341.0).ok);
  EXPECT_DOUBLE_EQ(AnchorInitialPose(340.1, h, 341.0).t, 340.1);
  EXPECT_DOUBLE_EQ(AnchorInitialPose(0.0, h, 341.0).t, 341.0);      // "now"
  EXPECT_DOUBLE_EQ(AnchorInitialPose(341.005, h, 341.0).t, 341.0);  // never extrapolated
  EXPECT_DOUBLE_EQ(AnchorInitialPose(345.0, h, 341.0).t, 341.0);    // not covered yet
  EXPECT_FALSE(AnchorInitialPose(340.1, tracking::OdometryHistory(), -1e300).ok);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
