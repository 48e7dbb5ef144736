// Mosaic retention: after three versions, pruning keeps exactly the tile rows the kept versions
// show (the current tiles byte-identical) and deletes folded, refused and long-waiting patches by
// age, keeping the recent unfolded ones.
#include "mosaic/mosaic_retention.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "mapping/changed_floor_scene.h"
#include "mosaic/importer.h"
#include "mosaic/test_util.h"
#include "mosaic_upkeep/remap_job.h"

namespace fleetloc::mosaic {
// The re-mapping job makes the versions retention prunes.
using mosaic_upkeep::RemapMode;
using mosaic_upkeep::RunRemap;
using mosaic_upkeep::VehicleStandingStore;
namespace {

using Scene = mapping::testing::ChangedFloorScene;
constexpr double kRes = Scene::kRes;
constexpr double kDay = 86400;

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

class MosaicRetentionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(cv::imwrite(dir_.File("floor.png"), scene_.old_floor));
    path_ = dir_.File("floor.db");
    ImportOptions options;
    options.resolution_m = kRes;
    ASSERT_TRUE(ImportImage(dir_.File("floor.png"), options, path_).ok());
    store_ = std::move(TileStore::Open(path_, OpenMode::kReadWrite)).value();
    patches_ = std::move(PatchStore::Open(path_)).value();
    standing_ = std::move(VehicleStandingStore::Open(path_)).value();
  }

  void Put(int64_t sequence, cv::Point centre) {
    const mapping::Patch p = scene_.PatchAt(centre, {});
    ASSERT_EQ(*patches_->Put({"agv-1", sequence, 1.0, p.pose, p.covariance, 0.9, p.image}),
              PutOutcome::kStored);
  }
  long long Count(const std::string& sql) {
    sqlite3* db = nullptr;
    sqlite3_open(path_.c_str(), &db);
    sqlite3_stmt* stmt = nullptr;
    sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr);
    const long long n = sqlite3_step(stmt) == SQLITE_ROW ? sqlite3_column_int64(stmt, 0) : -1;
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return n;
  }
  MapRect Everywhere() const { return {0, 0, 1024 * kRes, 1024 * kRes}; }

  Scene scene_;
  testing::ScratchDir dir_;  // removed with the fixture
  std::string path_;
  std::unique_ptr<TileStore> store_;
  std::unique_ptr<PatchStore> patches_;
  std::unique_ptr<VehicleStandingStore> standing_;
};

TEST_F(MosaicRetentionTest, KeepsTheTilesOfTheKeptVersionsAndDropsOldPatches) {
  Put(1, {490, 425});
  ASSERT_EQ(
      RunRemap(*store_, *patches_, *standing_, {Everywhere(), RemapMode::kReplace})->new_version,
      2);
  Put(2, {470, 440});
  ASSERT_EQ(
      RunRemap(*store_, *patches_, *standing_, {Everywhere(), RemapMode::kReplace})->new_version,
      3);
  Put(3, {300, 300});  // waits for a re-map
  const auto current = store_->ReadTileBytes({0, 1, 1});
  const long long rows = Count("SELECT COUNT(*) FROM tiles");
  const long long changed_twice = Count(
      "SELECT COUNT(*) FROM (SELECT 1 FROM tiles GROUP BY level, col, row HAVING COUNT(*) = 3)");
  ASSERT_GT(changed_twice, 0);

  // Keep versions 2 and 3: each tile changed in both re-maps loses only its version-1 row.
  Result<PruneResult> kept_two = PruneMosaic(path_, {2, 7 * kDay, 90 * kDay}, Now());
  ASSERT_TRUE(kept_two.ok()) << kept_two.status().message();
  EXPECT_EQ(kept_two->mosaic_version, 3);
  EXPECT_EQ(kept_two->oldest_version_kept, 2);
  EXPECT_EQ(kept_two->tile_rows_deleted, changed_twice);
  EXPECT_EQ(kept_two->patches_deleted, 0);  // all younger than the retention
  // Keep only version 3: a tile changed in version 2 alone also loses its version-1 row.
  Result<PruneResult> kept_one = PruneMosaic(path_, {1, 7 * kDay, 90 * kDay}, Now());
  ASSERT_TRUE(kept_one.ok());
  EXPECT_EQ(Count("SELECT COUNT(*) FROM (SELECT 1 FROM tiles GROUP BY level, col, row HAVING "
                  "COUNT(*) > 1)"),
            0);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM tiles") + kept_two->tile_rows_deleted +
                kept_one->tile_rows_deleted,
            rows);
  ASSERT_TRUE(store_->Refresh().ok());
  EXPECT_EQ(*store_->ReadTileBytes({0, 1, 1}), *current);  // what is served does not change

  // Eight days later the two folded patches go; the waiting one stays until 90 days.
  Result<PruneResult> later = PruneMosaic(path_, {1, 7 * kDay, 90 * kDay}, Now() + 8 * kDay);
  ASSERT_TRUE(later.ok());
  EXPECT_EQ(later->patches_deleted, 2);
  EXPECT_GT(later->patch_bytes_deleted, 10000);
  EXPECT_EQ(patches_->Counts(3)->stored, 1);
  EXPECT_EQ(PruneMosaic(path_, {1, 7 * kDay, 90 * kDay}, Now() + 91 * kDay)->patches_deleted, 1);
  EXPECT_EQ(PruneMosaic(path_, {0, 1, 1}, Now()).status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(PruneMosaic(dir_.File("missing.db"), {}, Now()).status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::mosaic
