// Deleting superseded tile versions, their place indexes and old patches.
#include "mosaic/mosaic_retention.h"

#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <initializer_list>

#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic {
namespace {

constexpr int kBusyTimeoutMs = 10000;

// A tile row older than the oldest kept version is deleted when a newer row of the same tile is at
// or below that version (that newer row is what the oldest kept version shows).
constexpr const char* kDeleteTiles =
    "DELETE FROM tiles WHERE version < ?1 AND EXISTS (SELECT 1 FROM tiles AS newer"
    " WHERE newer.level = tiles.level AND newer.col = tiles.col AND newer.row = tiles.row"
    " AND newer.version > tiles.version AND newer.version <= ?1)";

bool TableExists(sqlite3* db, const char* table) {
  Result<sqlite::Stmt> stmt =
      sqlite::Prepare(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?1");
  if (!stmt.ok()) return false;
  sqlite3_bind_text(stmt->get(), 1, table, -1, SQLITE_STATIC);
  return sqlite3_step(stmt->get()) == SQLITE_ROW;
}

// Runs `sql` with the given double parameters; the rows it changed.
Result<long long> Run(sqlite3* db, const char* sql, std::initializer_list<double> params) {
  Result<sqlite::Stmt> stmt = sqlite::Prepare(db, sql);
  if (!stmt.ok()) return stmt.status();
  int i = 0;
  for (double p : params) sqlite3_bind_double(stmt->get(), ++i, p);
  if (sqlite3_step(stmt->get()) != SQLITE_DONE) return Internal(sqlite::ErrorMessage(db));
  return static_cast<long long>(sqlite3_changes(db));
}

Result<long long> CommittedVersion(sqlite3* db, const std::string& path) {
  Result<sqlite::Stmt> stmt =
      sqlite::Prepare(db, "SELECT value FROM metadata WHERE name = 'version'");
  if (!stmt.ok() || sqlite3_step(stmt->get()) != SQLITE_ROW) {
    return InvalidInput(path + ": not a fleetloc mosaic (no version in its metadata)");
  }
  return static_cast<long long>(sqlite3_column_int64(stmt->get(), 0));
}

// The patches to delete: folded at or below the committed version, or refused, and stored before
// `done_before`; or never folded and stored before `waiting_before`.
constexpr const char* kOldPatches =
    " FROM patches WHERE ((((folded_in_version > 0 AND folded_in_version <= ?1) OR refused_reason "
    "IS NOT NULL)"
    " AND received < ?2) OR ((folded_in_version = 0 OR folded_in_version > ?1) AND refused_reason "
    "IS NULL"
    " AND received < ?3))";

Status PruneInTransaction(sqlite3* db, const std::string& path, const RetentionPolicy& policy,
                          double now_s, PruneResult* r) {
  Result<long long> version = CommittedVersion(db, path);
  if (!version.ok()) return version.status();
  r->mosaic_version = *version;
  r->oldest_version_kept = std::max(0LL, *version - policy.tile_versions_kept + 1);
  const double oldest = static_cast<double>(r->oldest_version_kept);
  Result<long long> tiles = Run(db, kDeleteTiles, {oldest});
  if (!tiles.ok()) return tiles.status();
  r->tile_rows_deleted = *tiles;
  if (TableExists(db, "place_index")) {
    Result<long long> indexes =
        Run(db, "DELETE FROM place_index WHERE mosaic_version < ?1", {oldest});
    if (!indexes.ok()) return indexes.status();
    r->place_indexes_deleted = *indexes;
  }
  if (!TableExists(db, "patches")) return Status::Ok();
  const std::initializer_list<double> params = {static_cast<double>(*version),
                                                now_s - policy.patch_retention_s,
                                                now_s - policy.unfolded_patch_retention_s};
  Result<sqlite::Stmt> count =
      sqlite::Prepare(db, std::string("SELECT COUNT(*), TOTAL(LENGTH(image))") + kOldPatches);
  if (!count.ok()) return count.status();
  int i = 0;
  for (double p : params) sqlite3_bind_double(count->get(), ++i, p);
  if (sqlite3_step(count->get()) != SQLITE_ROW) return Internal(sqlite::ErrorMessage(db));
  r->patch_bytes_deleted = static_cast<long long>(sqlite3_column_double(count->get(), 1));
  Result<long long> patches = Run(db, (std::string("DELETE") + kOldPatches).c_str(), params);
  if (!patches.ok()) return patches.status();
  r->patches_deleted = *patches;
  return Status::Ok();
}

long long FileBytes(const std::string& path) {
  std::error_code ec;
  long long bytes = 0;
  for (const char* suffix : {"", "-wal"}) {
    const auto size = std::filesystem::file_size(path + suffix, ec);
    if (!ec) bytes += static_cast<long long>(size);
  }
  return bytes;
}

}  // namespace

std::string RetentionProblem(const RetentionPolicy& p) {
  if (p.tile_versions_kept < 1) return "tile_versions_kept must be >= 1";
  if (!(p.patch_retention_s >= 0)) return "patch_retention_s must be >= 0";
  if (!(p.unfolded_patch_retention_s >= 0)) return "unfolded_patch_retention_s must be >= 0";
  return "";
}

Result<PruneResult> PruneMosaic(const std::string& path, const RetentionPolicy& policy,
                                double now_s, bool vacuum) {
  if (const std::string problem = RetentionProblem(policy); !problem.empty()) {
    return InvalidInput("retention: " + problem);
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path + ": no such mosaic file");
  Result<sqlite::Db> db = sqlite::OpenDb(path, SQLITE_OPEN_READWRITE);
  if (!db.ok()) return db.status();
  sqlite3_busy_timeout(db->get(), kBusyTimeoutMs);
  PruneResult result;
  result.file_bytes_before = FileBytes(path);
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db->get(), "BEGIN IMMEDIATE"));
  if (Status pruned = PruneInTransaction(db->get(), path, policy, now_s, &result); !pruned.ok()) {
    (void)sqlite::Exec(db->get(), "ROLLBACK");
    return Internal(path + ": pruning: " + pruned.message());
  }
  if (Status committed = sqlite::Exec(db->get(), "COMMIT"); !committed.ok()) {
    return Internal(path + ": pruning: " + committed.message());
  }
  if (vacuum) {
    if (Status vacuumed = sqlite::Exec(db->get(), "VACUUM"); !vacuumed.ok()) {
      return Internal(path + ": vacuum: " + vacuumed.message());
    }
  }
  (void)sqlite::Exec(db->get(), "PRAGMA wal_checkpoint(TRUNCATE)");
  result.file_bytes_after = FileBytes(path);
  return result;
}

}  // namespace fleetloc::mosaic
