// Tests for the SQLite tile store: round trip, versions, crash atomicity, and rejection of files
// that are not fleetloc mosaics.
#include "mosaic/tile_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "mosaic/importer.h"
#include "mosaic/test_util.h"

namespace fleetloc::mosaic {
namespace {

using testing::LoadGray;
using testing::MaxAbsDiff;
using testing::ScratchDir;
using testing::SourcePath;

constexpr char kPhoto[] = "tests/data/gravel.png";  // 512 x 512: 4 + 1 tiles of 256

// Imports the test photo into `path` (version 1).
void ImportPhoto(const std::string& path) {
  ImportOptions options;
  options.resolution_m = 0.001;
  Result<MosaicLayout> layout = ImportImage(SourcePath(kPhoto), options, path);
  ASSERT_TRUE(layout.ok()) << layout.status().message();
}

std::unique_ptr<TileStore> OpenOrDie(const std::string& path, OpenMode mode) {
  Result<std::unique_ptr<TileStore>> store = TileStore::Open(path, mode);
  EXPECT_TRUE(store.ok()) << store.status().message();
  return store.ok() ? std::move(store).value() : nullptr;
}

// A tile of constant value, to tell versions apart.
cv::Mat Flat(int value) { return cv::Mat(256, 256, CV_8UC1, cv::Scalar(value)); }

// Runs SQL on a database file directly (to forge broken mosaics).
void RawSql(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);
}

// Expects Open to fail with InvalidInput whose message names the file and contains `what`.
void ExpectRejected(const std::string& path, const std::string& what) {
  Result<std::unique_ptr<TileStore>> store = TileStore::Open(path, OpenMode::kReadOnly);
  ASSERT_FALSE(store.ok()) << path;
  EXPECT_EQ(store.status().code(), StatusCode::kInvalidInput) << store.status().message();
  EXPECT_EQ(store.status().message().rfind(path + ": ", 0), 0u) << store.status().message();
  EXPECT_NE(store.status().message().find(what), std::string::npos) << store.status().message();
}

TEST(TileStore, ImportedPhotoReadsBackWithMetadata) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  std::unique_ptr<TileStore> store = OpenOrDie(dir.File("m.db"), OpenMode::kReadOnly);
  ASSERT_NE(store, nullptr);
  const MosaicLayout layout = store->layout();
  EXPECT_EQ(layout.width_px, 512);
  EXPECT_EQ(layout.levels, 2);
  EXPECT_EQ(layout.version, 1);
  EXPECT_EQ(layout.mosaic_id.size(), 32u);
  EXPECT_DOUBLE_EQ(layout.geo.origin_y, 0.512);
  const cv::Mat gray = LoadGray(SourcePath(kPhoto));
  Result<cv::Mat> tile = store->ReadTile({0, 1, 1});
  ASSERT_TRUE(tile.ok()) << tile.status().message();
  EXPECT_EQ(MaxAbsDiff(*tile, gray(cv::Rect(256, 256, 256, 256))), 0);
  EXPECT_EQ(store->ReadTile({0, 2, 0}).status().code(), StatusCode::kNotFound);
  EXPECT_EQ(*store->TileCountsPerLevel(), (std::vector<long long>{4, 1}));
  EXPECT_EQ(store->ReadMetadata()->at("format"), "fleetloc-mosaic/1");
  store.reset();  // the last reader to close leaves no WAL side files behind
  EXPECT_FALSE(std::filesystem::exists(dir.File("m.db-wal")));
  EXPECT_FALSE(std::filesystem::exists(dir.File("m.db-shm")));
}

TEST(TileStore, ReadsNewestVersionNotAboveTheCurrentOne) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  std::unique_ptr<TileStore> writer = OpenOrDie(dir.File("m.db"), OpenMode::kReadWrite);
  std::unique_ptr<TileStore> reader = OpenOrDie(dir.File("m.db"), OpenMode::kReadOnly);
  const cv::Mat original = *reader->ReadTile({0, 0, 0});
  ASSERT_TRUE(writer->BeginVersion().ok());
  ASSERT_TRUE(writer->PutTile({0, 0, 0}, Flat(200)).ok());
  EXPECT_EQ(MaxAbsDiff(*writer->ReadTile({0, 0, 0}), original), 0);  // not yet committed
  ASSERT_EQ(*writer->CommitVersion(), 2);
  EXPECT_EQ(writer->ReadTile({0, 0, 0})->at<std::uint8_t>(9, 9), 200);
  EXPECT_EQ(MaxAbsDiff(*writer->ReadTile({0, 1, 0}), *reader->ReadTile({0, 1, 0})), 0);
  // The reader keeps its version until it refreshes.
  EXPECT_EQ(MaxAbsDiff(*reader->ReadTile({0, 0, 0}), original), 0);
  EXPECT_EQ(*reader->Refresh(), 2);
  EXPECT_EQ(reader->ReadTile({0, 0, 0})->at<std::uint8_t>(9, 9), 200);
  EXPECT_EQ(*reader->TileCountsPerLevel(), (std::vector<long long>{4, 1}));
}

TEST(TileStore, TileLookupSearchesThePrimaryKeyIndexInsteadOfScanning) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  std::unique_ptr<TileStore> reader = OpenOrDie(dir.File("m.db"), OpenMode::kReadOnly);
  Result<std::string> plan = reader->TileLookupPlan();
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  // All three key columns and the version bound are used by the index search: O(log tiles).
  EXPECT_NE(plan->find("SEARCH tiles USING INDEX sqlite_autoindex_tiles_1 (level=? AND col=? AND "
                       "row=? AND version<?)"),
            std::string::npos)
      << *plan;
  EXPECT_EQ(plan->find("SCAN"), std::string::npos) << *plan;
  EXPECT_EQ(plan->find("TEMP B-TREE"), std::string::npos) << *plan;  // no sort for ORDER BY
}

TEST(TileStore, ReopenAfterCrashKeepsLastCommittedVersion) {
  ScratchDir dir;
  const std::string path = dir.File("m.db");
  ImportPhoto(path);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // writer that dies in the middle of version 2
    Result<std::unique_ptr<TileStore>> store = TileStore::Open(path, OpenMode::kReadWrite);
    if (!store.ok() || !(*store)->BeginVersion().ok()) _exit(3);
    cv::Mat noise(256, 256, CV_8UC1);
    for (int i = 0; i < 60; ++i) {  // enough data to spill pages into the WAL
      cv::randu(noise, 0, 256);
      if (!(*store)->PutTile({0, i % 2, (i / 2) % 2}, noise).ok()) _exit(4);
    }
    _exit(0);  // no commit, no rollback, no close
  }
  int wait_status = 0;
  ASSERT_EQ(waitpid(child, &wait_status, 0), child);
  ASSERT_TRUE(WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0);
  const cv::Mat gray = LoadGray(SourcePath(kPhoto));
  for (const OpenMode mode : {OpenMode::kReadOnly, OpenMode::kReadWrite}) {
    std::unique_ptr<TileStore> store = OpenOrDie(path, mode);
    ASSERT_NE(store, nullptr);
    EXPECT_EQ(store->version(), 1);
    EXPECT_EQ(MaxAbsDiff(*store->ReadTile({0, 0, 0}), gray(cv::Rect(0, 0, 256, 256))), 0);
  }
  // The next writer commits version 2 normally, and it survives reopening.
  std::unique_ptr<TileStore> writer = OpenOrDie(path, OpenMode::kReadWrite);
  ASSERT_TRUE(writer->BeginVersion().ok());
  ASSERT_TRUE(writer->PutTile({1, 0, 0}, Flat(9)).ok());
  ASSERT_EQ(*writer->CommitVersion(), 2);
  writer.reset();
  std::unique_ptr<TileStore> reopened = OpenOrDie(path, OpenMode::kReadOnly);
  EXPECT_EQ(reopened->version(), 2);
  EXPECT_EQ(reopened->ReadTile({1, 0, 0})->at<std::uint8_t>(0, 0), 9);
}

TEST(TileStore, ClosingWithoutCommitOrAbortingDiscardsTheVersion) {
  ScratchDir dir;
  const std::string path = dir.File("m.db");
  ImportPhoto(path);
  {
    std::unique_ptr<TileStore> store = OpenOrDie(path, OpenMode::kReadWrite);
    ASSERT_TRUE(store->BeginVersion().ok());
    ASSERT_TRUE(store->PutTile({0, 0, 0}, Flat(1)).ok());
  }  // destroyed mid-version
  std::unique_ptr<TileStore> store = OpenOrDie(path, OpenMode::kReadWrite);
  EXPECT_EQ(store->version(), 1);
  ASSERT_TRUE(store->BeginVersion().ok());
  ASSERT_TRUE(store->PutTile({0, 0, 0}, Flat(1)).ok());
  ASSERT_TRUE(store->AbortVersion().ok());
  EXPECT_EQ(*store->Refresh(), 1);
  const cv::Mat gray = LoadGray(SourcePath(kPhoto));
  EXPECT_EQ(MaxAbsDiff(*store->ReadTile({0, 0, 0}), gray(cv::Rect(0, 0, 256, 256))), 0);
  EXPECT_EQ(*store->TileCountsPerLevel(), (std::vector<long long>{4, 1}));
}

TEST(TileStore, PutTileRejectsKeysOutsideTheGridAndBadTiles) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  std::unique_ptr<TileStore> store = OpenOrDie(dir.File("m.db"), OpenMode::kReadWrite);
  ASSERT_TRUE(store->BeginVersion().ok());
  EXPECT_EQ(store->PutTile({0, 2, 0}, Flat(1)).code(), StatusCode::kInvalidInput);
  EXPECT_EQ(store->PutTile({1, 0, 1}, Flat(1)).code(), StatusCode::kInvalidInput);
  EXPECT_EQ(store->PutTile({2, 0, 0}, Flat(1)).code(), StatusCode::kInvalidInput);
  EXPECT_EQ(store->PutTile({0, 0, 0}, cv::Mat(128, 128, CV_8UC1)).code(),
            StatusCode::kInvalidInput);
  EXPECT_EQ(store->PutTile({0, 0, 0}, cv::Mat(256, 256, CV_8UC3)).code(),
            StatusCode::kInvalidInput);
  ASSERT_TRUE(store->AbortVersion().ok());
  std::unique_ptr<TileStore> reader = OpenOrDie(dir.File("m.db"), OpenMode::kReadOnly);
  EXPECT_EQ(reader->BeginVersion().code(), StatusCode::kInvalidInput);
}

TEST(TileStore, CreateRefusesExistingFileAndInvalidLayout) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  MosaicLayout layout;
  layout.width_px = 100;
  layout.height_px = 100;
  layout.geo.resolution = 0.001;
  EXPECT_EQ(TileStore::Create(dir.File("m.db"), layout).status().code(), StatusCode::kInvalidInput);
  layout.levels = 3;  // 100 px fits one 256 tile: must be 1
  EXPECT_EQ(TileStore::Create(dir.File("new.db"), layout).status().code(),
            StatusCode::kInvalidInput);
  layout.levels = 1;
  Result<std::unique_ptr<TileStore>> created = TileStore::Create(dir.File("new.db"), layout);
  ASSERT_TRUE(created.ok()) << created.status().message();
  EXPECT_EQ((*created)->version(), 0);
  EXPECT_EQ((*created)->ReadTile({0, 0, 0}).status().code(), StatusCode::kNotFound);
}

TEST(TileStore, RejectsFilesThatAreNotMosaics) {
  ScratchDir dir;
  std::ofstream(dir.File("notes.txt")) << "this is a text file, not a mosaic\n";
  ExpectRejected(dir.File("notes.txt"), "not a fleetloc mosaic");
  std::ofstream(dir.File("empty.db")).close();
  ExpectRejected(dir.File("empty.db"), "metadata");
  RawSql(dir.File("other.db"), "CREATE TABLE things(a INTEGER); INSERT INTO things VALUES(1);");
  ExpectRejected(dir.File("other.db"), "no such table: metadata");
  EXPECT_EQ(TileStore::Open(dir.File("absent.db"), OpenMode::kReadOnly).status().code(),
            StatusCode::kNotFound);
}

TEST(TileStore, RejectsTruncatedCopiesOfARealMosaic) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  const std::string bytes = testing::ReadFileBytes(dir.File("m.db"));
  ASSERT_GT(bytes.size(), 100000u);
  for (const double fraction : {0.001, 0.02, 0.3, 0.6, 0.95, 0.999}) {
    const std::string path = dir.File("cut" + std::to_string(fraction) + ".db");
    testing::WriteFileBytes(path, bytes, static_cast<std::size_t>(bytes.size() * fraction));
    ExpectRejected(path, "not a fleetloc mosaic");
  }
}

TEST(TileStore, RejectsWrongOrMissingOrNonsenseMetadata) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  const struct {
    const char* sql;
    const char* expected;
  } cases[] = {
      {"UPDATE metadata SET value = 'mbtiles/1' WHERE name = 'format'", "'format' = 'mbtiles/1'"},
      {"DELETE FROM metadata WHERE name = 'tile_size'", "'tile_size' is missing"},
      {"DELETE FROM metadata WHERE name = 'created'", "'created' is missing"},
      {"UPDATE metadata SET value = '-5' WHERE name = 'width'", "'width' = '-5' is outside"},
      {"UPDATE metadata SET value = '512px' WHERE name = 'height'", "is not an integer"},
      {"UPDATE metadata SET value = 'abc' WHERE name = 'resolution'", "not a finite number"},
      {"UPDATE metadata SET value = 'nan' WHERE name = 'origin_x'", "not a finite number"},
      {"UPDATE metadata SET value = '0' WHERE name = 'resolution'", "resolution must be"},
      {"UPDATE metadata SET value = '7' WHERE name = 'levels'", "levels is 7 but must be 2"},
      {"UPDATE metadata SET value = '100' WHERE name = 'tile_size'", "power of two"},
      {"UPDATE metadata SET value = 'xyz' WHERE name = 'mosaic_id'", "not 32 hex digits"},
      {"UPDATE metadata SET value = NULL WHERE name = 'version'", "'version' = ''"},
      {"DROP TABLE tiles", "tiles table"},
      {"ALTER TABLE tiles RENAME COLUMN version TO v", "tiles table"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const std::string path = dir.File("bad" + std::to_string(n++) + ".db");
    std::filesystem::copy_file(dir.File("m.db"), path);
    RawSql(path, c.sql);
    ExpectRejected(path, c.expected);
  }
}

TEST(TileStore, LoaderFeedsViewsOnSeveralThreads) {
  ScratchDir dir;
  ImportPhoto(dir.File("m.db"));
  std::shared_ptr<TileStore> store = OpenOrDie(dir.File("m.db"), OpenMode::kReadOnly);
  auto cache = std::make_shared<TileCache>(2 * 256 * 256);  // small: forces reloads
  const cv::Mat gray = LoadGray(SourcePath(kPhoto));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      MosaicView view(store->layout(), MakeTileLoader(store), cache);
      for (int i = 0; i < 50; ++i) {
        const cv::Rect rect((i * 37 + t * 101) % 400, (i * 53 + t * 29) % 400, 100, 90);
        EXPECT_EQ(MaxAbsDiff(view.ReadBlock(0, rect), gray(rect)), 0) << rect;
      }
      EXPECT_EQ(view.missing_tiles() + view.unreadable_tiles(), 0);
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_GT(cache->stats().evictions, 0);
}

}  // namespace
}  // namespace fleetloc::mosaic
