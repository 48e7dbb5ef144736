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
    if (sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr) == SQLITE_OK &&
        sqlite3_step(stmt) == SQLITE_ROW) {
      value = sqlite3_column_int64(stmt, 0);
    }
    sqlite3_finalize(stmt);
  }
  sqlite3_close(db);
  return value;
}

// How many patches the agent's outbox at `outbox` ever queued (its sequence numbers so far).
inline long long QueuedPatches(const std::string& outbox) {
  return SqliteValue(outbox, "SELECT value - 1 FROM meta WHERE name = 'next_sequence'");
}

// How many of the patches `vehicle` queued in `outbox` were acknowledged (gone from it; what is
// left there is sent again at the next start) but are not stored in the mosaic file `mosaic`.
inline long long AcknowledgedButMissing(const std::string& outbox, const std::string& vehicle,
                                        const std::string& mosaic) {
  const std::string sql =
      "WITH RECURSIVE queued(n) AS (SELECT 1 UNION ALL SELECT n + 1 FROM queued"
      " WHERE n < (SELECT value - 1 FROM meta WHERE name = 'next_sequence'))"
      " SELECT COUNT(*) FROM queued WHERE (SELECT value - 1 FROM meta WHERE name = "
      "'next_sequence') > 0"
      " AND n NOT IN (SELECT sequence FROM outbox)"
      " AND n NOT IN (SELECT sequence FROM server.patches WHERE vehicle_id = '" +
      vehicle + "')";
  return SqliteValue(outbox, sql.c_str(), {{"server", mosaic}});
}

}  // namespace fleetloc::testing
