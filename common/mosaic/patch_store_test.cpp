// Patch store: idempotent puts, exact read-back, reopen, bad fields (a malformed covariance among
// them), corrupt blobs, folding that only counts once the mosaic version is committed, refusals
// that are never selected again, and files written before refusals existed.
#include "mosaic/patch_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>

#include "mosaic/importer.h"
#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

class PatchStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.File("floor.db");
    ImportOptions options;
    options.resolution_m = 0.0005;
    ASSERT_TRUE(ImportImage(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", options, path_).ok());
  }

  static PatchRecord Patch(int64_t sequence) {
    PatchRecord p;
    p.vehicle_id = "agv-7";
    p.sequence = sequence;
    p.stamp_s = 12.5;
    p.pose = {0.1, 0.12, 0.3};
    p.covariance = Eigen::Vector3d(1e-6, 2e-6, 1e-5).asDiagonal();
    p.quality = 0.8;
    p.image = cv::Mat(60, 80, CV_8UC1);
    cv::randu(p.image, 0, 255);
    return p;
  }
  std::unique_ptr<PatchStore> Open() {
    auto store = PatchStore::Open(path_);
    EXPECT_TRUE(store.ok()) << store.status().message();
    return std::move(store).value();
  }

  testing::ScratchDir dir_;  // removed with the fixture
  std::string path_;
  const MapRect everywhere_{-10, -10, 10, 10};
};

TEST_F(PatchStoreTest, StoresOnceAndReadsBackExactly) {
  auto store = Open();
  const PatchRecord patch = Patch(1);
  EXPECT_EQ(*store->Put(patch), PutOutcome::kStored);
  EXPECT_EQ(*store->Put(patch), PutOutcome::kDuplicate);
  auto got = store->Unfolded(everywhere_, 1);
  ASSERT_TRUE(got.ok());
  ASSERT_EQ(got->patches.size(), 1u);
  const PatchRecord& p = got->patches[0];
  EXPECT_EQ(p.vehicle_id, "agv-7");
  EXPECT_EQ(p.sequence, 1);
  EXPECT_EQ(p.stamp_s, 12.5);
  EXPECT_EQ(p.pose.theta, 0.3);
  EXPECT_EQ(p.covariance, patch.covariance);
  EXPECT_EQ(p.quality, 0.8);
  EXPECT_EQ(cv::norm(p.image, patch.image, cv::NORM_INF), 0);
  EXPECT_EQ(store->Counts(1)->stored, 1);
}

TEST_F(PatchStoreTest, ReopenKeepsEveryPatchAndRegionQueriesSelect) {
  {
    auto store = Open();
    PatchRecord far = Patch(2);
    far.pose = {5.0, 5.0, 0.0};
    ASSERT_TRUE(store->Put(Patch(1)).ok());
    ASSERT_TRUE(store->Put(far).ok());
  }
  auto store = Open();
  EXPECT_EQ(store->Unfolded(everywhere_, 1)->patches.size(), 2u);
  EXPECT_EQ(store->Unfolded({0.0, 0.0, 0.2, 0.2}, 1)->patches.size(), 1u);
}

TEST_F(PatchStoreTest, BadFieldsAreNamed) {
  auto store = Open();
  PatchRecord nan_pose = Patch(1), bad_quality = Patch(2), empty = Patch(3);
  PatchRecord zero_covariance = Patch(4), negative_covariance = Patch(5);
  nan_pose.pose.x = std::nan("");
  bad_quality.quality = 2;
  empty.image.release();
  zero_covariance.covariance.setZero();
  negative_covariance.covariance *= -1;
  EXPECT_NE(store->Put(nan_pose).status().message().find("pose"), std::string::npos);
  EXPECT_NE(store->Put(bad_quality).status().message().find("quality"), std::string::npos);
  EXPECT_NE(store->Put(empty).status().message().find("image"), std::string::npos);
  for (const PatchRecord* p : {&zero_covariance, &negative_covariance}) {
    EXPECT_NE(
        store->Put(*p).status().message().find("covariance': covariance is not positive definite"),
        std::string::npos)
        << store->Put(*p).status().message();
  }
  EXPECT_EQ(store->Counts(1)->stored, 0);
}

TEST_F(PatchStoreTest, CorruptStoredImageIsCountedAndSkipped) {
  auto store = Open();
  ASSERT_TRUE(store->Put(Patch(1)).ok());
  ASSERT_TRUE(store->Put(Patch(2)).ok());
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(db, "UPDATE patches SET image = x'89504e470d0a1a0a0000' WHERE sequence = 2",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  sqlite3_close(db);
  auto got = store->Unfolded(everywhere_, 1);
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(got->patches.size(), 1u);
  EXPECT_EQ(got->unreadable, 1);
}

TEST_F(PatchStoreTest, FoldingCountsOnlyOnceTheVersionIsCommitted) {
  auto store = Open();
  ASSERT_TRUE(store->Put(Patch(1)).ok());
  ASSERT_TRUE(store->MarkFolded({Patch(1)}, 2).ok());
  EXPECT_EQ(store->Unfolded(everywhere_, 1)->patches.size(), 1u);  // version 2 not committed
  EXPECT_EQ(store->Unfolded(everywhere_, 2)->patches.size(), 0u);  // committed: folded
  EXPECT_EQ(store->Counts(2)->folded, 1);
  ASSERT_TRUE(store->ClearUncommittedMarks(1).ok());  // the job died before commit
  EXPECT_EQ(store->Unfolded(everywhere_, 2)->patches.size(), 1u);
}

TEST_F(PatchStoreTest, RefusedPatchesAreNeverSelectedAgain) {
  auto store = Open();
  ASSERT_TRUE(store->Put(Patch(1)).ok());
  ASSERT_TRUE(store->Put(Patch(2)).ok());
  ASSERT_TRUE(store->MarkRefused({{"agv-7", 2, "unregistered: does not register"}}).ok());
  const auto unfolded = store->Unfolded(everywhere_, 1);
  ASSERT_EQ(unfolded->patches.size(), 1u);
  EXPECT_EQ(unfolded->patches[0].sequence, 1);
  EXPECT_EQ(store->Counts(1)->refused, 1);
  EXPECT_EQ(store->Counts(1)->stored, 2);
}

TEST_F(PatchStoreTest, AFileWrittenBeforeRefusalsExistedGainsTheColumn) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
  // The patches table as earlier versions made it, with one patch in it.
  ASSERT_EQ(
      sqlite3_exec(db,
                   "CREATE TABLE patches(vehicle_id TEXT NOT NULL, sequence INTEGER NOT NULL,"
                   " stamp REAL NOT NULL, x REAL NOT NULL, y REAL NOT NULL, theta REAL NOT NULL,"
                   " covariance BLOB NOT NULL, quality REAL NOT NULL, min_x REAL NOT NULL,"
                   " min_y REAL NOT NULL, max_x REAL NOT NULL, max_y REAL NOT NULL,"
                   " image BLOB NOT NULL, folded_in_version INTEGER NOT NULL DEFAULT 0,"
                   " PRIMARY KEY(vehicle_id, sequence))",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  sqlite3_close(db);
  auto store = Open();
  ASSERT_TRUE(store->Put(Patch(1)).ok());
  ASSERT_TRUE(store->MarkRefused({{"agv-7", 1, "flat"}}).ok());
  EXPECT_EQ(store->Counts(1)->refused, 1);
}

TEST_F(PatchStoreTest, AFileThatIsNotAMosaicIsRejected) {
  const std::string text = dir_.File("notes.txt");
  std::ofstream(text) << "not a database";
  auto store = PatchStore::Open(text);
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("notes.txt"), std::string::npos);
  EXPECT_EQ(PatchStore::Open(dir_.File("missing.db")).status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::mosaic
