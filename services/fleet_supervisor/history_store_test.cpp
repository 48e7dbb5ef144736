// HistoryStore: rows round-trip, ranges, retention, restart.
#include "fleet_supervisor/history_store.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace fleetloc::fleet_supervisor {
namespace {

constexpr double kT0 = 1.7e9;

std::string TempDb(const std::string& name) {
  const auto path =
      std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".db");
  sqlite::RemoveDatabaseFiles(path.string());
  return path.string();
}

StoredPose Pose(const std::string& id, double t, double x) {
  StoredPose p;
  p.vehicle_id = id;
  p.received = t + 0.01;
  p.pose.t = t;
  p.pose.x = x;
  p.pose.y = -x;
  p.pose.theta = 0.5;
  p.pose.cov_xx = 1e-6;
  p.pose.lock = localization::LockState::kCoasting;
  p.pose.deviation_range_m = 0.003;
  p.pose.mosaic_version = 2;
  return p;
}

StoredHealth Health(const std::string& id, double t, double p95) {
  StoredHealth h;
  h.vehicle_id = id;
  h.received = t + 0.02;
  h.health.t = t;
  h.health.cycle_ms_p95 = p95;
  h.health.issues = {"coasting", "tile_timeouts"};
  h.health.level = fleet::HealthLevel::kWarn;
  h.health.camera_frame_drops = 7;
  h.health.map_server_reachable = false;
  h.health.last_error = "tile 0/1/2 timed out";
  return h;
}

TEST(HistoryStore, RowsRoundTripAndRangesAreOldestFirstWithTheNewestKept) {
  const std::string path = TempDb("history_rows");
  auto store = HistoryStore::Open(path);
  ASSERT_TRUE(store.ok()) << store.status().message();
  std::vector<StoredPose> poses;
  std::vector<StoredHealth> health;
  poses.reserve(100);
  health.reserve(10);
  for (int i = 0; i < 100; ++i) poses.push_back(Pose("agv-1", kT0 + i, i * 0.1));
  for (int i = 0; i < 10; ++i) health.push_back(Health("agv-1", kT0 + 10 * i, 2.0 + i));
  poses.push_back(Pose("agv-2", kT0 + 5, 9.0));
  ASSERT_TRUE((*store)->Append(poses, health).ok());

  auto range = (*store)->Poses("agv-1", kT0 + 10, kT0 + 50, 5);
  ASSERT_TRUE(range.ok());
  ASSERT_EQ(range->size(), 5u);
  // Received 0.01 s after their stamps: the newest 5 received in [10, 50], oldest first.
  EXPECT_DOUBLE_EQ(range->front().pose.t, kT0 + 45);
  EXPECT_DOUBLE_EQ(range->back().pose.x, 4.9);
  EXPECT_EQ(range->back().pose.lock, localization::LockState::kCoasting);
  EXPECT_EQ(range->back().pose.mosaic_version, 2);
  auto h = (*store)->Health("agv-1", kT0, kT0 + 1000, 100);
  ASSERT_TRUE(h.ok());
  ASSERT_EQ(h->size(), 10u);
  EXPECT_DOUBLE_EQ(h->back().health.cycle_ms_p95, 11.0);
  EXPECT_EQ(h->back().health.issues, (std::vector<std::string>{"coasting", "tile_timeouts"}));
  EXPECT_FALSE(h->back().health.map_server_reachable);
  EXPECT_EQ(h->back().health.camera_frame_drops, 7u);
  EXPECT_EQ(h->back().health.last_error, "tile 0/1/2 timed out");
  EXPECT_TRUE((*store)->Poses("agv-3", kT0, kT0 + 100, 10)->empty());
  sqlite::RemoveDatabaseFiles(path);
}

TEST(HistoryStore, RetentionDeletesOldRowsAndClearedAlertsOnly) {
  const std::string path = TempDb("history_retention");
  auto store = HistoryStore::Open(path);
  ASSERT_TRUE(store.ok());
  std::vector<StoredPose> poses;
  poses.reserve(100);
  for (int i = 0; i < 100; ++i) poses.push_back(Pose("agv-1", kT0 + i, i));
  ASSERT_TRUE(
      (*store)->Append(poses, {Health("agv-1", kT0, 2), Health("agv-1", kT0 + 90, 2)}).ok());
  auto old_cleared = (*store)->InsertAlert({0,
                                            "agv-1",
                                            fleet::AlertKind::kCycleOverrun,
                                            fleet::Severity::kWarning,
                                            kT0 + 1,
                                            {},
                                            "slow"});
  auto old_open = (*store)->InsertAlert(
      {0, "agv-1", fleet::AlertKind::kSilent, fleet::Severity::kCritical, kT0 + 2, {}, "silent"});
  ASSERT_TRUE(old_cleared.ok() && old_open.ok());
  EXPECT_GT(*old_open, *old_cleared);
  ASSERT_TRUE((*store)->CloseAlert(*old_cleared, kT0 + 5).ok());
  auto deleted = (*store)->Prune(kT0 + 60);
  ASSERT_TRUE(deleted.ok());
  EXPECT_EQ(*deleted, 60 + 1 + 1);  // 60 poses, 1 health row, 1 cleared alert
  EXPECT_EQ((*store)->Poses("agv-1", 0, kT0 + 1000, 1000)->size(), 40u);
  auto alerts = (*store)->Alerts({});
  ASSERT_EQ(alerts->size(), 1u);
  EXPECT_EQ(alerts->front().kind, fleet::AlertKind::kSilent);
  EXPECT_FALSE(alerts->front().cleared_t.has_value());
  sqlite::RemoveDatabaseFiles(path);
}

TEST(HistoryStore, ReopenedStoreGivesEachVehiclesNewestStateAndOpenAlerts) {
  const std::string path = TempDb("history_reopen");
  {
    auto store = HistoryStore::Open(path);
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(
        (*store)
            ->Append({Pose("agv-1", kT0, 1), Pose("agv-1", kT0 + 1, 2), Pose("agv-2", kT0 + 3, 7)},
                     {Health("agv-1", kT0 + 4, 3.5)})
            .ok());
    ASSERT_TRUE((*store)
                    ->InsertAlert({0,
                                   "agv-2",
                                   fleet::AlertKind::kLockLost,
                                   fleet::Severity::kCritical,
                                   kT0 + 3,
                                   {},
                                   "lost"})
                    .ok());
  }
  auto store = HistoryStore::Open(path);
  ASSERT_TRUE(store.ok());
  auto vehicles = (*store)->LatestVehicles();
  ASSERT_TRUE(vehicles.ok()) << vehicles.status().message();
  ASSERT_EQ(vehicles->size(), 2u);
  const fleet::VehicleState& v1 = (*vehicles)[0];
  EXPECT_EQ(v1.id, "agv-1");
  EXPECT_DOUBLE_EQ(v1.pose->x, 2.0);
  EXPECT_DOUBLE_EQ(v1.health->cycle_ms_p95, 3.5);
  EXPECT_DOUBLE_EQ(v1.last_seen, kT0 + 4.02);
  EXPECT_FALSE((*vehicles)[1].health.has_value());
  auto open = (*store)->Alerts({"agv-2", true, 10});
  ASSERT_EQ(open->size(), 1u);
  EXPECT_EQ(open->front().kind, fleet::AlertKind::kLockLost);
  EXPECT_TRUE(*(*store)->KnowsVehicle("agv-2"));
  EXPECT_FALSE(*(*store)->KnowsVehicle("agv-5"));
  sqlite::RemoveDatabaseFiles(path);
}

TEST(HistoryStore, AFileThatIsNotAHistoryIsRefused) {
  const std::string path = TempDb("history_foreign");
  {
    auto store = HistoryStore::Open(path);
    ASSERT_TRUE(store.ok());
  }
  {
    sqlite::Db db = std::move(sqlite::OpenDb(path, 2).value());
    ASSERT_TRUE(sqlite::Exec(db.get(), "UPDATE history_meta SET value = 'other/9'").ok());
  }
  auto store = HistoryStore::Open(path);
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("not a fleetloc history"), std::string::npos);
  sqlite::RemoveDatabaseFiles(path);
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
