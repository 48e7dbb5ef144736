// The SQLite helpers: a file that cannot be opened is named, SQL errors carry SQLite's message, a
// reset guard leaves no read open and no binding behind, and a database's side files go with it.
#include "sqlite/sqlite_util.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>

namespace fleetloc::sqlite {
namespace {

namespace fs = std::filesystem;

fs::path TempPath(const std::string& name) {
  return fs::temp_directory_path() / ("fleetloc_sqlite_util_test_" + name);
}

TEST(SqliteUtil, AFileThatCannotBeOpenedIsNamed) {
  const std::string path = (TempPath("missing_dir") / "no" / "db.sqlite").string();
  Result<Db> db = OpenDb(path, SQLITE_OPEN_READWRITE);
  ASSERT_FALSE(db.ok());
  EXPECT_NE(db.status().message().find(path), std::string::npos) << db.status().message();
}

TEST(SqliteUtil, SqlErrorsCarrySqlitesMessage) {
  Result<Db> db = OpenDb(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  ASSERT_TRUE(db.ok()) << db.status().message();
  const Status bad = Exec(db->get(), "CREATE TABLEX t (a)");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("syntax error"), std::string::npos) << bad.message();
  Result<Stmt> missing = Prepare(db->get(), "SELECT a FROM nowhere");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("no such table"), std::string::npos);
}

TEST(SqliteUtil, AScopedResetClearsBindingsAndEndsTheRead) {
  Result<Db> db = OpenDb(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  ASSERT_TRUE(db.ok());
  ASSERT_TRUE(Exec(db->get(), "CREATE TABLE t (a INTEGER); INSERT INTO t VALUES (1), (2);").ok());
  Result<Stmt> select = Prepare(db->get(), "SELECT ?1, a FROM t");
  ASSERT_TRUE(select.ok());
  {
    ScopedReset reset(select->get());
    sqlite3_bind_int(select->get(), 1, 42);
    ASSERT_EQ(sqlite3_step(select->get()), SQLITE_ROW);  // a read left half done
    EXPECT_EQ(sqlite3_column_int(select->get(), 0), 42);
    EXPECT_NE(sqlite3_stmt_busy(select->get()), 0);
  }
  EXPECT_EQ(sqlite3_stmt_busy(select->get()), 0);
  ASSERT_EQ(sqlite3_step(select->get()), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_type(select->get(), 0), SQLITE_NULL);  // the binding is gone
}

TEST(SqliteUtil, RemovingADatabaseRemovesItsSideFiles) {
  const std::string path = TempPath("side_files.db").string();
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::ofstream(path + suffix) << "x";
  RemoveDatabaseFiles(path);
  for (const char* suffix : {"", "-wal", "-shm", "-journal"})
    EXPECT_FALSE(fs::exists(path + suffix));
  RemoveDatabaseFiles(path);  // absent files are no error
}

}  // namespace
}  // namespace fleetloc::sqlite
