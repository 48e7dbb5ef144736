// One integer read from an SQLite file by a test (a count of stored patches, an outbox's size),
// read-only, so a running service's file can be inspected; -1 when it cannot be read. Other files
// can be attached under schema names for queries across them.
#pragma once

#include <sqlite3.h>

#include <string>
#include <utility>
#include <vector>

namespace fleetloc::testing {

inline long long SqliteValue(const std::string& path, const char* sql,
                             const std::vector<std::pair<std::string, std::string>>& attach = {}) {
  sqlite3* db = nullptr;
  long long value = -1;
  bool ok = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK;
  for (const auto& [schema, file] : attach) {
    const std::string statement = "ATTACH DATABASE '" + file + "' AS " + schema;
    ok = ok && sqlite3_exec(db, statement.c_str(), nullptr, nullptr, nullptr) == SQLITE_OK;
  }
  if (ok) {
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
