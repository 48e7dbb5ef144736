// The place_index table of a mosaic file (see place_index_store.h).
#include "mosaic/place_index_store.h"

#include <sqlite3.h>

#include <filesystem>

#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic {
namespace {

constexpr int kBusyTimeoutMs = 10000;
constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS place_index(mosaic_version INTEGER NOT NULL, key TEXT NOT NULL,"
    " data BLOB NOT NULL, PRIMARY KEY(mosaic_version, key));";

Result<sqlite::Db> OpenMosaicFile(const std::string& path, int flags) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path + ": no such mosaic file");
  Result<sqlite::Db> db = sqlite::OpenDb(path, flags);
  if (db.ok()) sqlite3_busy_timeout(db->get(), kBusyTimeoutMs);
  return db;
}

bool HasTable(sqlite3* db) {
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'place_index'");
  return stmt.ok() && sqlite3_step(stmt->get()) == SQLITE_ROW;
}

}  // namespace

Result<std::optional<std::vector<std::uint8_t>>> ReadPlaceIndexBlob(const std::string& mosaic_path,
                                                                    long long mosaic_version,
                                                                    const std::string& key) {
  Result<sqlite::Db> db = OpenMosaicFile(mosaic_path, SQLITE_OPEN_READONLY);
  if (!db.ok()) return db.status();
  if (!HasTable(db->get())) return std::optional<std::vector<std::uint8_t>>();
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db->get(), "SELECT data FROM place_index WHERE mosaic_version = ? AND key = ?");
  if (!stmt.ok()) return Internal(mosaic_path + ": " + stmt.status().message());
  sqlite3_bind_int64(stmt->get(), 1, mosaic_version);
  sqlite3_bind_text(stmt->get(), 2, key.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(stmt->get());
  if (rc == SQLITE_DONE) return std::optional<std::vector<std::uint8_t>>();
  if (rc != SQLITE_ROW) return Internal(mosaic_path + ": " + sqlite::ErrorMessage(db->get()));
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt->get(), 0));
  const int bytes = sqlite3_column_bytes(stmt->get(), 0);
  return std::optional<std::vector<std::uint8_t>>(std::vector<std::uint8_t>(data, data + bytes));
}

Status WritePlaceIndexBlob(const std::string& mosaic_path, long long mosaic_version,
                           const std::string& key, std::span<const std::uint8_t> blob) {
  Result<sqlite::Db> db = OpenMosaicFile(mosaic_path, SQLITE_OPEN_READWRITE);
  if (!db.ok()) return db.status();
  sqlite3* handle = db->get();
  const auto fail = [&](const std::string& what) {
    (void)sqlite::Exec(handle, "ROLLBACK");  // the error reported is the one that made us roll back
    return Internal(mosaic_path + ": storing the place index: " + what);
  };
  if (Status s = sqlite::Exec(handle, "BEGIN IMMEDIATE"); !s.ok()) return fail(s.message());
  if (Status s = sqlite::Exec(handle, kSchema); !s.ok()) return fail(s.message());
  Result<sqlite::Stmt> remove =
      sqlite::Prepare(handle, "DELETE FROM place_index WHERE key = ? AND mosaic_version <> ?");
  Result<sqlite::Stmt> insert = sqlite::Prepare(
      handle, "INSERT OR REPLACE INTO place_index(mosaic_version, key, data) VALUES (?, ?, ?)");
  if (!remove.ok() || !insert.ok()) return fail(sqlite::ErrorMessage(handle));
  sqlite3_bind_text(remove->get(), 1, key.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(remove->get(), 2, mosaic_version);
  sqlite3_bind_int64(insert->get(), 1, mosaic_version);
  sqlite3_bind_text(insert->get(), 2, key.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_blob64(insert->get(), 3, blob.data(), blob.size(), SQLITE_STATIC);
  if (sqlite3_step(remove->get()) != SQLITE_DONE || sqlite3_step(insert->get()) != SQLITE_DONE)
    return fail(sqlite::ErrorMessage(handle));
  if (Status s = sqlite::Exec(handle, "COMMIT"); !s.ok()) return fail(s.message());
  return Status::Ok();
}

}  // namespace fleetloc::mosaic
