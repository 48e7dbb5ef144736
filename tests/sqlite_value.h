// One integer read from an SQLite file by a test (a count of stored patches, an outbox's size),
// read-only, so a running service's file can be inspected; -1 when it cannot be read.
#pragma once

#include <sqlite3.h>

#include <string>

namespace fleetloc::testing {

inline long long SqliteValue(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  long long value = -1;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr) == SQLITE_OK && sqlite3_step(stmt) == SQLITE_ROW) {
      value = sqlite3_column_int64(stmt, 0);
    }
    sqlite3_finalize(stmt);
  }
  sqlite3_close(db);
  return value;
}

}  // namespace fleetloc::testing
