// The vehicle_standing table in the mosaic file.
#include "mosaic_upkeep/vehicle_standing_store.h"

#include <sqlite3.h>

#include <filesystem>

namespace fleetloc::mosaic_upkeep {
namespace {

constexpr int kBusyTimeoutMs = 10000;

constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS vehicle_standing("
    " vehicle_id TEXT PRIMARY KEY, admitted INTEGER NOT NULL, refused INTEGER NOT NULL,"
    " recent TEXT NOT NULL, quarantined INTEGER NOT NULL, reason TEXT NOT NULL)";

std::string Text(sqlite3_stmt* s, int column) {
  const unsigned char* text = sqlite3_column_text(s, column);
  return text != nullptr ? reinterpret_cast<const char*>(text) : "";
}

}  // namespace

Result<std::unique_ptr<VehicleStandingStore>> VehicleStandingStore::Open(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path + ": no such mosaic file");
  Result<sqlite::Db> db = sqlite::OpenDb(path, SQLITE_OPEN_READWRITE);
  if (!db.ok()) return db.status();
  sqlite3_busy_timeout(db->get(), kBusyTimeoutMs);
  if (Status created = sqlite::Exec(db->get(), kSchema); !created.ok()) {
    return Internal(path + ": cannot create the vehicle_standing table: " + created.message());
  }
  return std::unique_ptr<VehicleStandingStore>(
      new VehicleStandingStore(path, std::move(db).value()));
}

Result<std::map<std::string, mapping::VehicleStanding>> VehicleStandingStore::Select(
    const std::string* vehicle_id) {
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(), vehicle_id != nullptr
                     ? "SELECT vehicle_id, admitted, refused, recent, quarantined, reason"
                       " FROM vehicle_standing WHERE vehicle_id = ?1"
                     : "SELECT vehicle_id, admitted, refused, recent, quarantined, reason"
                       " FROM vehicle_standing ORDER BY vehicle_id");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_stmt* s = stmt->get();
  if (vehicle_id != nullptr) sqlite3_bind_text(s, 1, vehicle_id->c_str(), -1, SQLITE_TRANSIENT);
  std::map<std::string, mapping::VehicleStanding> out;
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    mapping::VehicleStanding v;
    v.admitted = sqlite3_column_int64(s, 1);
    v.refused = sqlite3_column_int64(s, 2);
    v.recent = Text(s, 3);
    v.quarantined = sqlite3_column_int(s, 4) != 0;
    v.reason = Text(s, 5);
    out[Text(s, 0)] = std::move(v);
  }
  if (rc != SQLITE_DONE) {
    return Internal(path_ + ": reading vehicle standing: " + sqlite::ErrorMessage(db_.get()));
  }
  return out;
}

Result<std::map<std::string, mapping::VehicleStanding>> VehicleStandingStore::All() {
  std::lock_guard lock(mutex_);
  return Select(nullptr);
}

Result<mapping::VehicleStanding> VehicleStandingStore::Get(const std::string& vehicle_id) {
  std::lock_guard lock(mutex_);
  auto found = Select(&vehicle_id);
  if (!found.ok()) return found.status();
  return found->empty() ? mapping::VehicleStanding{} : found->begin()->second;
}

Result<bool> VehicleStandingStore::IsQuarantined(const std::string& vehicle_id) {
  Result<mapping::VehicleStanding> standing = Get(vehicle_id);
  if (!standing.ok()) return standing.status();
  return standing->quarantined;
}

Status VehicleStandingStore::PutAll(
    const std::map<std::string, mapping::VehicleStanding>& standings) {
  std::lock_guard lock(mutex_);
  return PutAllLocked(standings);
}

Status VehicleStandingStore::PutAllLocked(
    const std::map<std::string, mapping::VehicleStanding>& standings) {
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db_.get(), "BEGIN IMMEDIATE"));
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "INSERT OR REPLACE INTO vehicle_standing(vehicle_id, admitted, refused, recent, quarantined,"
      " reason) VALUES(?1, ?2, ?3, ?4, ?5, ?6)");
  bool ok = stmt.ok();
  for (auto it = standings.begin(); ok && it != standings.end(); ++it) {
    sqlite::ScopedReset reset(stmt->get());
    sqlite3_stmt* s = stmt->get();
    sqlite3_bind_text(s, 1, it->first.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(s, 2, it->second.admitted);
    sqlite3_bind_int64(s, 3, it->second.refused);
    sqlite3_bind_text(s, 4, it->second.recent.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int(s, 5, it->second.quarantined ? 1 : 0);
    sqlite3_bind_text(s, 6, it->second.reason.c_str(), -1, SQLITE_TRANSIENT);
    ok = sqlite3_step(s) == SQLITE_DONE;
  }
  if (!ok) {
    const std::string message = sqlite::ErrorMessage(db_.get());
    (void)sqlite::Exec(db_.get(), "ROLLBACK");
    return Internal(path_ + ": writing vehicle standing: " + message);
  }
  return sqlite::Exec(db_.get(), "COMMIT");
}

Status VehicleStandingStore::Release(const std::string& vehicle_id) {
  std::lock_guard lock(mutex_);
  auto found = Select(&vehicle_id);
  if (!found.ok()) return found.status();
  if (found->empty()) return NotFound(path_ + ": vehicle '" + vehicle_id + "' has no standing");
  mapping::Release(&found->begin()->second);
  return PutAllLocked(*found);
}

}  // namespace fleetloc::mosaic_upkeep
