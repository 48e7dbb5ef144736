// FleetState: samples, trails, silence and the alert rules on scripted vehicles.
#include "fleet/fleet_state.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet {
namespace {

using localization::LockState;
constexpr double kT0 = 1.7e9;

PoseSample Pose(double t, double x, LockState lock = LockState::kTracking, double dev_m = 0.001) {
  PoseSample p;
  p.t = t;
  p.x = x;
  p.y = 2.0;
  p.lock = lock;
  p.deviation_range_m = dev_m;
  return p;
}

HealthSample Health(double t, double cycle_p95_ms, std::uint64_t drops = 0, bool reachable = true) {
  HealthSample h;
  h.t = t;
  h.cycle_ms_p95 = cycle_p95_ms;
  h.camera_frame_drops = drops;
  h.map_server_reachable = reachable;
  return h;
}

// Feeds one vehicle a pose at 10 Hz and a health report at 1 Hz from `from` to `to` (seconds
// after kT0), evaluating at 10 Hz; returns every alert change.
template <typename PoseFn, typename HealthFn>
std::vector<AlertChange> Drive(FleetState* fleet, double from, double to, PoseFn pose,
                               HealthFn health) {
  std::vector<AlertChange> changes;
  for (int i = static_cast<int>(from * 10); i < static_cast<int>(to * 10); ++i) {
    const double t = kT0 + i / 10.0;
    fleet->OnPose("agv-1", pose(t), t);
    if (i % 10 == 0) fleet->OnHealth("agv-1", health(t), t);
    for (const AlertChange& c : fleet->Evaluate(t)) changes.push_back(c);
  }
  return changes;
}

TEST(FleetState, KeepsTheNewestPoseAndATrailAtTheTrailPeriod) {
  FleetState fleet({}, {/*period_s=*/0.5, /*length_s=*/10.0});
  for (int i = 0; i <= 200; ++i)
    fleet.OnPose("agv-1", Pose(kT0 + i * 0.1, i * 0.01), kT0 + i * 0.1);
  fleet.OnPose("agv-1", Pose(kT0 + 5.0, -1.0), kT0 + 20.1);  // late, older sample: ignored
  const VehicleState* v = fleet.Find("agv-1");
  ASSERT_NE(v, nullptr);
  EXPECT_DOUBLE_EQ(v->pose->x, 2.0);
  EXPECT_EQ(v->poses, 201);
  // 20 s at one point per 0.5 s, only the last 10 s kept: 21 points, 0.5 s apart.
  ASSERT_EQ(v->trail.size(), 21u);
  EXPECT_NEAR(v->trail.back().t - v->trail.front().t, 10.0, 1e-6);
  EXPECT_EQ(fleet.Find("agv-2"), nullptr);
}

TEST(FleetState, ASilentVehicleIsRaisedAfterTheTimeoutAndClearedWhenItTalksAgain) {
  FleetState fleet({}, {});  // silent: > 3 s raises, < 1 s for 1 s clears
  auto tracking = [](double t) { return Pose(t, 1.0); };
  auto healthy = [](double t) { return Health(t, 2.0); };
  EXPECT_TRUE(Drive(&fleet, 0, 5, tracking, healthy).empty());
  // Nothing arrives from t=5; evaluation goes on.
  std::vector<AlertChange> changes;
  for (int i = 50; i < 100; ++i) {
    for (const AlertChange& c : fleet.Evaluate(kT0 + i / 10.0)) changes.push_back(c);
  }
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0].kind, AlertKind::kSilent);
  EXPECT_EQ(changes[0].severity, Severity::kCritical);
  EXPECT_NEAR(changes[0].raised_t - kT0, 8.0, 0.11);  // last seen at 4.9 s, + 3 s
  EXPECT_TRUE(fleet.Silent("agv-1"));
  EXPECT_EQ(fleet.Summary().silent, 1);
  changes = Drive(&fleet, 10, 13, tracking, healthy);
  EXPECT_EQ(fleet.Summary().tracking, 1);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_TRUE(changes[0].cleared_t.has_value());
  EXPECT_NEAR(*changes[0].cleared_t - kT0, 11.0, 0.11);  // 1 s of data flowing again
  EXPECT_TRUE(fleet.ActiveAlerts().empty());
}

TEST(FleetState, AStaleVehicleIsCountedAsSilentNotByItsLastLockState) {
  FleetState fleet({}, {});
  Drive(
      &fleet, 0, 5, [](double t) { return Pose(t, 1.0); }, [](double t) { return Health(t, 2.0); });
  fleet.OnPose("agv-2", Pose(kT0 + 4.9, 3.0, LockState::kCoasting), kT0 + 4.9);
  EXPECT_EQ(fleet.Summary().tracking, 1);
  EXPECT_EQ(fleet.Summary().coasting, 1);
  fleet.Evaluate(kT0 + 8.5);  // both last seen at 4.9 s: silent after 3 s
  const FleetSummary summary = fleet.Summary();
  EXPECT_EQ(summary.vehicles, 2);
  EXPECT_EQ(summary.silent, 2);
  EXPECT_EQ(
      summary.tracking + summary.coasting + summary.lost + summary.relocalized + summary.unknown,
      0);
}

TEST(FleetState, LostLockRaisesACriticalAlertAfterOneSecond) {
  FleetState fleet({}, {});
  auto pose = [](double t) {
    return Pose(t, 1.0, t - kT0 >= 2.0 && t - kT0 < 6.0 ? LockState::kLost : LockState::kTracking);
  };
  const std::vector<AlertChange> changes =
      Drive(&fleet, 0, 10, pose, [](double t) { return Health(t, 2.0); });
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[0].kind, AlertKind::kLockLost);
  EXPECT_NEAR(changes[0].raised_t - kT0, 3.0, 0.11);    // lost at 2 s, held 1 s
  EXPECT_NEAR(*changes[1].cleared_t - kT0, 8.0, 0.11);  // tracking again at 6 s, held 2 s
}

TEST(FleetState, GrowingUncertaintyRaisesAWarningAndClearsWithHysteresis) {
  FleetState fleet({}, {});  // raise > 20 mm for 1 s, clear < 10 mm for 3 s
  // Coasting: 3-sigma deviation grows 5 mm/s from 1 mm, then relocks at 8 s back to 1 mm.
  auto pose = [](double t) {
    const double s = t - kT0;
    return Pose(t, 1.0, s < 8 ? LockState::kCoasting : LockState::kTracking,
                s < 8 ? 0.001 + 0.005 * s : 0.001);
  };
  const std::vector<AlertChange> changes =
      Drive(&fleet, 0, 15, pose, [](double t) { return Health(t, 2.0); });
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[0].kind, AlertKind::kUncertainty);
  EXPECT_EQ(changes[0].severity, Severity::kWarning);
  EXPECT_NEAR(changes[0].raised_t - kT0, 4.9, 0.11);  // 20 mm crossed at 3.8 s, held 1 s
  EXPECT_NEAR(*changes[1].cleared_t - kT0, 11.0, 0.11);
}

TEST(FleetState, CycleOverrunCameraDropsAndUnreachableMapServer) {
  FleetState fleet({}, {});
  // p95 cycle 80 ms from 2 s to 9 s; 3 drops per second from 4 s to 6 s; map server away from 3 s.
  auto health = [](double t) {
    const double s = t - kT0;
    const std::uint64_t drops = s < 4 ? 0 : static_cast<std::uint64_t>(3 * (std::min(s, 6.0) - 4));
    return Health(t, s >= 2 && s < 9 ? 80.0 : 2.0, drops, s < 3);
  };
  const std::vector<AlertChange> changes = Drive(
      &fleet, 0, 25, [](double t) { return Pose(t, 1.0); }, health);
  std::map<AlertKind, std::vector<AlertChange>> by_kind;
  for (const AlertChange& c : changes) by_kind[c.kind].push_back(c);
  ASSERT_EQ(by_kind[AlertKind::kCycleOverrun].size(), 2u);
  EXPECT_NEAR(by_kind[AlertKind::kCycleOverrun][0].raised_t - kT0, 5.0, 0.11);     // 2 s + 3 s hold
  EXPECT_NEAR(*by_kind[AlertKind::kCycleOverrun][1].cleared_t - kT0, 14.0, 0.11);  // 9 s + 5 s
  ASSERT_EQ(by_kind[AlertKind::kCameraDrops].size(), 2u);
  EXPECT_NEAR(by_kind[AlertKind::kCameraDrops][0].raised_t - kT0, 5.0, 0.11);  // first rate at 5 s
  EXPECT_NEAR(*by_kind[AlertKind::kCameraDrops][1].cleared_t - kT0, 17.0,
              0.11);  // rate 0 at 7 s + 10 s
  ASSERT_EQ(by_kind[AlertKind::kMapServerUnreachable].size(), 1u);
  EXPECT_NEAR(by_kind[AlertKind::kMapServerUnreachable][0].raised_t - kT0, 6.0, 0.11);
  const FleetSummary summary = fleet.Summary();
  EXPECT_EQ(summary.warning_alerts, 1);
  EXPECT_EQ(summary.tracking, 1);
}

TEST(FleetState, RestoredOpenAlertsStayActiveAndAreNotRaisedTwice) {
  FleetState fleet({}, {});
  VehicleState v;
  v.id = "agv-9";
  v.pose = Pose(kT0, 3.0);
  v.last_seen = kT0;
  fleet.Restore(v);
  fleet.RestoreAlert(
      {17, "agv-9", AlertKind::kSilent, Severity::kCritical, kT0 + 3, std::nullopt, "silent"});
  EXPECT_TRUE(fleet.Evaluate(kT0 + 100).empty());
  ASSERT_EQ(fleet.ActiveAlerts().size(), 1u);
  EXPECT_EQ(fleet.ActiveAlerts()[0].id, 17);
}

}  // namespace
}  // namespace fleetloc::fleet
