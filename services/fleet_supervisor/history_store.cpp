// HistoryStore over SQLite.
#include "fleet_supervisor/history_store.h"

#include <sqlite3.h>

#include <algorithm>
#include <map>
#include <sstream>

namespace fleetloc::fleet_supervisor {

using fleet::Alert;

namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS history_meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
INSERT OR IGNORE INTO history_meta VALUES('format', 'fleetloc-history/1');
CREATE TABLE IF NOT EXISTS poses(vehicle TEXT NOT NULL, t REAL NOT NULL, received REAL NOT NULL,
  x REAL, y REAL, theta REAL, cov_xx REAL, cov_xy REAL, cov_yy REAL, cov_tt REAL,
  lock INTEGER, score REAL, deviation_m REAL, mosaic_version INTEGER);
CREATE INDEX IF NOT EXISTS poses_by_vehicle ON poses(vehicle, received);
CREATE TABLE IF NOT EXISTS health(vehicle TEXT NOT NULL, t REAL NOT NULL, received REAL NOT NULL,
  level INTEGER, issues TEXT, lock INTEGER, cycle_p50 REAL, cycle_p95 REAL, cycle_p99 REAL,
  inliers INTEGER, cache_hit_rate REAL, tiles_pending INTEGER, patch_outbox INTEGER,
  reachable INTEGER, drops INTEGER, last_error TEXT);
CREATE INDEX IF NOT EXISTS health_by_vehicle ON health(vehicle, received);
CREATE TABLE IF NOT EXISTS alerts(id INTEGER PRIMARY KEY AUTOINCREMENT, vehicle TEXT NOT NULL,
  kind TEXT NOT NULL, severity TEXT NOT NULL, raised REAL NOT NULL, cleared REAL, message TEXT);
CREATE INDEX IF NOT EXISTS alerts_by_raised ON alerts(raised);
)sql";

constexpr const char* kPoseColumns =
    "vehicle, t, received, x, y, theta, cov_xx, cov_xy, cov_yy, cov_tt, lock, score, deviation_m, "
    "mosaic_version";
constexpr const char* kHealthColumns =
    "vehicle, t, received, level, issues, lock, cycle_p50, cycle_p95, cycle_p99, inliers, "
    "cache_hit_rate, tiles_pending, patch_outbox, reachable, drops, last_error";

std::string Text(sqlite3_stmt* s, int column) {
  const unsigned char* text = sqlite3_column_text(s, column);
  return text ? reinterpret_cast<const char*>(text) : "";
}

void BindText(sqlite3_stmt* s, int index, const std::string& text) {
  sqlite3_bind_text(s, index, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
}

std::string JoinIssues(const std::vector<std::string>& issues) {
  std::string joined;
  for (const std::string& issue : issues) joined += (joined.empty() ? "" : ",") + issue;
  return joined;
}

std::vector<std::string> SplitIssues(const std::string& joined) {
  std::vector<std::string> issues;
  std::stringstream in(joined);
  for (std::string issue; std::getline(in, issue, ',');) {
    if (!issue.empty()) issues.push_back(issue);
  }
  return issues;
}

void BindPose(sqlite3_stmt* s, const StoredPose& r) {
  const fleet::PoseSample& p = r.pose;
  BindText(s, 1, r.vehicle_id);
  const double values[] = {p.t,      r.received, p.x,      p.y,     p.theta,
                           p.cov_xx, p.cov_xy,   p.cov_yy, p.cov_tt};
  for (int i = 0; i < 9; ++i) sqlite3_bind_double(s, 2 + i, values[i]);
  sqlite3_bind_int(s, 11, static_cast<int>(p.lock));
  sqlite3_bind_double(s, 12, p.localization_score);
  sqlite3_bind_double(s, 13, p.deviation_range_m);
  sqlite3_bind_int64(s, 14, p.mosaic_version);
}

StoredPose ReadPose(sqlite3_stmt* s) {
  StoredPose r;
  r.vehicle_id = Text(s, 0);
  r.received = sqlite3_column_double(s, 2);
  fleet::PoseSample& p = r.pose;
  double* targets[] = {&p.t,      nullptr,   &p.x,      &p.y,     &p.theta,
                       &p.cov_xx, &p.cov_xy, &p.cov_yy, &p.cov_tt};
  for (int i = 0; i < 9; ++i) {
    if (targets[i]) *targets[i] = sqlite3_column_double(s, 1 + i);
  }
  p.lock = static_cast<localization::LockState>(std::clamp(sqlite3_column_int(s, 10), 0, 3));
  p.localization_score = sqlite3_column_double(s, 11);
  p.deviation_range_m = sqlite3_column_double(s, 12);
  p.mosaic_version = sqlite3_column_int64(s, 13);
  return r;
}

void BindHealth(sqlite3_stmt* s, const StoredHealth& r) {
  const fleet::HealthSample& h = r.health;
  BindText(s, 1, r.vehicle_id);
  sqlite3_bind_double(s, 2, h.t);
  sqlite3_bind_double(s, 3, r.received);
  sqlite3_bind_int(s, 4, static_cast<int>(h.level));
  BindText(s, 5, JoinIssues(h.issues));
  sqlite3_bind_int(s, 6, static_cast<int>(h.lock));
  sqlite3_bind_double(s, 7, h.cycle_ms_p50);
  sqlite3_bind_double(s, 8, h.cycle_ms_p95);
  sqlite3_bind_double(s, 9, h.cycle_ms_p99);
  sqlite3_bind_int(s, 10, h.inliers);
  sqlite3_bind_double(s, 11, h.cache_hit_rate);
  sqlite3_bind_int(s, 12, h.tiles_pending);
  sqlite3_bind_int(s, 13, h.patch_outbox);
  sqlite3_bind_int(s, 14, h.map_server_reachable ? 1 : 0);
  sqlite3_bind_int64(s, 15, static_cast<sqlite3_int64>(h.camera_frame_drops));
  BindText(s, 16, h.last_error);
}

StoredHealth ReadHealth(sqlite3_stmt* s) {
  StoredHealth r;
  r.vehicle_id = Text(s, 0);
  fleet::HealthSample& h = r.health;
  h.t = sqlite3_column_double(s, 1);
  r.received = sqlite3_column_double(s, 2);
  h.level = static_cast<fleet::HealthLevel>(std::clamp(sqlite3_column_int(s, 3), 0, 3));
  h.issues = SplitIssues(Text(s, 4));
  h.lock = static_cast<localization::LockState>(std::clamp(sqlite3_column_int(s, 5), 0, 3));
  h.cycle_ms_p50 = sqlite3_column_double(s, 6);
  h.cycle_ms_p95 = sqlite3_column_double(s, 7);
  h.cycle_ms_p99 = sqlite3_column_double(s, 8);
  h.inliers = sqlite3_column_int(s, 9);
  h.cache_hit_rate = sqlite3_column_double(s, 10);
  h.tiles_pending = sqlite3_column_int(s, 11);
  h.patch_outbox = sqlite3_column_int(s, 12);
  h.map_server_reachable = sqlite3_column_int(s, 13) != 0;
  h.camera_frame_drops = static_cast<std::uint64_t>(sqlite3_column_int64(s, 14));
  h.last_error = Text(s, 15);
  return r;
}

Alert ReadAlert(sqlite3_stmt* s) {
  Alert a;
  a.id = sqlite3_column_int64(s, 0);
  a.vehicle_id = Text(s, 1);
  a.kind = fleet::AlertKindFromName(Text(s, 2)).value_or(fleet::AlertKind::kSilent);
  a.severity = Text(s, 3) == "critical" ? fleet::Severity::kCritical : fleet::Severity::kWarning;
  a.raised_t = sqlite3_column_double(s, 4);
  if (sqlite3_column_type(s, 5) != SQLITE_NULL) a.cleared_t = sqlite3_column_double(s, 5);
  a.message = Text(s, 6);
  return a;
}

// Steps `stmt` to the end, calling row(stmt) for each row. Internal with SQLite's message.
template <typename Fn>
Status Rows(sqlite3* db, sqlite3_stmt* stmt, Fn&& row) {
  for (;;) {
    const int rc = sqlite3_step(stmt);
    if (rc == SQLITE_DONE) return Status::Ok();
    if (rc != SQLITE_ROW) return Internal("history: " + sqlite::ErrorMessage(db));
    row(stmt);
  }
}

// Runs `sql` with `bind(stmt)` and collects read(stmt) for every row.
template <typename T, typename Bind, typename Read>
Result<std::vector<T>> Query(sqlite3* db, const std::string& sql, Bind&& bind, Read&& read) {
  Result<sqlite::Stmt> stmt = sqlite::Prepare(db, sql);
  if (!stmt.ok()) return stmt.status();
  bind(stmt->get());
  std::vector<T> rows;
  FLEETLOC_RETURN_IF_ERROR(
      Rows(db, stmt->get(), [&](sqlite3_stmt* s) { rows.push_back(read(s)); }));
  return rows;
}

// Newest-first rows in [from, to] of one vehicle, at most `limit`, returned oldest first.
template <typename T, typename Read>
Result<std::vector<T>> RangeOf(sqlite3* db, const char* table, const char* columns,
                               const std::string& vehicle, double from, double to, int limit,
                               Read&& read) {
  const std::string sql =
      std::string("SELECT ") + columns + " FROM " + table +
      " WHERE vehicle = ?1 AND received >= ?2 AND received <= ?3 ORDER BY received DESC LIMIT ?4";
  Result<std::vector<T>> rows = Query<T>(
      db, sql,
      [&](sqlite3_stmt* s) {
        BindText(s, 1, vehicle);
        sqlite3_bind_double(s, 2, from);
        sqlite3_bind_double(s, 3, to);
        sqlite3_bind_int(s, 4, limit);
      },
      read);
  if (rows.ok()) std::reverse(rows->begin(), rows->end());
  return rows;
}

}  // namespace

Result<std::unique_ptr<HistoryStore>> HistoryStore::Open(const std::string& path) {
  Result<sqlite::Db> db =
      sqlite::OpenDb(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX);
  if (!db.ok()) return db.status();
  std::unique_ptr<HistoryStore> store(new HistoryStore(std::move(db).value()));
  if (Status created = store->CreateSchema(); !created.ok()) {
    return InvalidInput(path + ": not a fleetloc history (" + created.message() + ")");
  }
  return store;
}

Status HistoryStore::CreateSchema() {
  FLEETLOC_RETURN_IF_ERROR(
      sqlite::Exec(db_.get(), "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;"));
  sqlite3_busy_timeout(db_.get(), 5000);
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db_.get(), kSchema));
  Result<std::vector<std::string>> format = Query<std::string>(
      db_.get(), "SELECT value FROM history_meta WHERE key = 'format'", [](sqlite3_stmt*) {},
      [](sqlite3_stmt* s) { return Text(s, 0); });
  if (!format.ok()) return format.status();
  if (format->size() != 1 || format->front() != "fleetloc-history/1") {
    return InvalidInput("unknown history format");
  }
  return Status::Ok();
}

Status HistoryStore::Append(const std::vector<StoredPose>& poses,
                            const std::vector<StoredHealth>& health) {
  if (poses.empty() && health.empty()) return Status::Ok();
  std::lock_guard lock(mutex_);
  sqlite3* db = db_.get();
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db, "BEGIN"));
  auto insert = [&](const std::string& sql, auto& rows, auto bind) -> Status {
    Result<sqlite::Stmt> stmt = sqlite::Prepare(db, sql);
    if (!stmt.ok()) return stmt.status();
    for (const auto& row : rows) {
      sqlite::ScopedReset reset(stmt->get());
      bind(stmt->get(), row);
      if (sqlite3_step(stmt->get()) != SQLITE_DONE)
        return Internal("history: " + sqlite::ErrorMessage(db));
    }
    return Status::Ok();
  };
  Status done = insert(std::string("INSERT INTO poses(") + kPoseColumns +
                           ") VALUES(?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14)",
                       poses, BindPose);
  if (done.ok()) {
    done = insert(std::string("INSERT INTO health(") + kHealthColumns +
                      ") VALUES(?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14,?15,?16)",
                  health, BindHealth);
  }
  if (!done.ok()) {
    (void)sqlite::Exec(db, "ROLLBACK");
    return done;
  }
  return sqlite::Exec(db, "COMMIT");
}

Result<long long> HistoryStore::InsertAlert(const Alert& a) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "INSERT INTO alerts(vehicle, kind, severity, raised, message) VALUES(?1,?2,?3,?4,?5)");
  if (!stmt.ok()) return stmt.status();
  BindText(stmt->get(), 1, a.vehicle_id);
  BindText(stmt->get(), 2, fleet::AlertKindName(a.kind));
  BindText(stmt->get(), 3, fleet::SeverityName(a.severity));
  sqlite3_bind_double(stmt->get(), 4, a.raised_t);
  BindText(stmt->get(), 5, a.message);
  if (sqlite3_step(stmt->get()) != SQLITE_DONE)
    return Internal("history: " + sqlite::ErrorMessage(db_.get()));
  return static_cast<long long>(sqlite3_last_insert_rowid(db_.get()));
}

Status HistoryStore::CloseAlert(long long id, double cleared_t) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt =
      sqlite::Prepare(db_.get(), "UPDATE alerts SET cleared = ?2 WHERE id = ?1");
  if (!stmt.ok()) return stmt.status();
  sqlite3_bind_int64(stmt->get(), 1, id);
  sqlite3_bind_double(stmt->get(), 2, cleared_t);
  if (sqlite3_step(stmt->get()) != SQLITE_DONE)
    return Internal("history: " + sqlite::ErrorMessage(db_.get()));
  return Status::Ok();
}

Result<long long> HistoryStore::Prune(double before) {
  std::lock_guard lock(mutex_);
  long long deleted = 0;
  for (const char* sql :
       {"DELETE FROM poses WHERE received < ?1", "DELETE FROM health WHERE received < ?1",
        "DELETE FROM alerts WHERE cleared IS NOT NULL AND cleared < ?1"}) {
    Result<sqlite::Stmt> stmt = sqlite::Prepare(db_.get(), sql);
    if (!stmt.ok()) return stmt.status();
    sqlite3_bind_double(stmt->get(), 1, before);
    if (sqlite3_step(stmt->get()) != SQLITE_DONE)
      return Internal("history: " + sqlite::ErrorMessage(db_.get()));
    deleted += sqlite3_changes(db_.get());
  }
  return deleted;
}

Result<std::vector<StoredPose>> HistoryStore::Poses(const std::string& vehicle, double from,
                                                    double to, int limit) {
  std::lock_guard lock(mutex_);
  return RangeOf<StoredPose>(db_.get(), "poses", kPoseColumns, vehicle, from, to, limit, ReadPose);
}

Result<std::vector<StoredHealth>> HistoryStore::Health(const std::string& vehicle, double from,
                                                       double to, int limit) {
  std::lock_guard lock(mutex_);
  return RangeOf<StoredHealth>(db_.get(), "health", kHealthColumns, vehicle, from, to, limit,
                               ReadHealth);
}

Result<std::vector<Alert>> HistoryStore::Alerts(const AlertQuery& q) {
  std::lock_guard lock(mutex_);
  std::string sql =
      "SELECT id, vehicle, kind, severity, raised, cleared, message FROM alerts WHERE 1";
  if (!q.vehicle_id.empty()) sql += " AND vehicle = ?1";
  if (q.active_only) sql += " AND cleared IS NULL";
  sql += " ORDER BY raised DESC, id DESC LIMIT ?2";
  return Query<Alert>(
      db_.get(), sql,
      [&](sqlite3_stmt* s) {
        if (!q.vehicle_id.empty()) BindText(s, 1, q.vehicle_id);
        sqlite3_bind_int(s, 2, q.limit);
      },
      ReadAlert);
}

Result<std::vector<fleet::VehicleState>> HistoryStore::LatestVehicles() {
  std::lock_guard lock(mutex_);
  std::map<std::string, fleet::VehicleState> vehicles;
  auto newest = [](const char* table, const char* columns) {
    return std::string("SELECT ") + columns + " FROM " + table +
           " r JOIN (SELECT vehicle AS v, MAX(received) AS mt FROM " + table +
           " GROUP BY vehicle) m ON r.vehicle = m.v AND r.received = m.mt";
  };
  Result<std::vector<StoredPose>> poses = Query<StoredPose>(
      db_.get(), newest("poses", kPoseColumns), [](sqlite3_stmt*) {}, ReadPose);
  if (!poses.ok()) return poses.status();
  Result<std::vector<StoredHealth>> health = Query<StoredHealth>(
      db_.get(), newest("health", kHealthColumns), [](sqlite3_stmt*) {}, ReadHealth);
  if (!health.ok()) return health.status();
  for (const StoredPose& p : *poses) {
    fleet::VehicleState& v = vehicles[p.vehicle_id];
    v.id = p.vehicle_id;
    v.pose = p.pose;
    v.last_seen = std::max(v.last_seen, p.received);
  }
  for (const StoredHealth& h : *health) {
    fleet::VehicleState& v = vehicles[h.vehicle_id];
    v.id = h.vehicle_id;
    v.health = h.health;
    v.last_seen = std::max(v.last_seen, h.received);
  }
  std::vector<fleet::VehicleState> out;
  out.reserve(vehicles.size());
  for (auto& [id, v] : vehicles) out.push_back(std::move(v));
  return out;
}

Result<bool> HistoryStore::KnowsVehicle(const std::string& vehicle_id) {
  std::lock_guard lock(mutex_);
  Result<std::vector<int>> found = Query<int>(
      db_.get(),
      "SELECT 1 FROM poses WHERE vehicle = ?1 UNION SELECT 1 FROM health WHERE vehicle = ?1 LIMIT "
      "1",
      [&](sqlite3_stmt* s) { BindText(s, 1, vehicle_id); }, [](sqlite3_stmt*) { return 1; });
  if (!found.ok()) return found.status();
  return !found->empty();
}

}  // namespace fleetloc::fleet_supervisor
