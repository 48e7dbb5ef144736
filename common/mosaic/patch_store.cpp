// The patches table in the mosaic file.
#include "mosaic/patch_store.h"

#include <sqlite3.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "geometry/covariance_check.h"
#include "mosaic/tile_codec.h"

namespace fleetloc::mosaic {
namespace {

constexpr int kBusyTimeoutMs = 10000;

constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS patches("
    " vehicle_id TEXT NOT NULL, sequence INTEGER NOT NULL, stamp REAL NOT NULL,"
    " x REAL NOT NULL, y REAL NOT NULL, theta REAL NOT NULL, covariance BLOB NOT NULL,"
    " quality REAL NOT NULL, min_x REAL NOT NULL, min_y REAL NOT NULL, max_x REAL NOT NULL,"
    " max_y REAL NOT NULL, image BLOB NOT NULL, folded_in_version INTEGER NOT NULL DEFAULT 0,"
    " refused_reason TEXT, received REAL, PRIMARY KEY(vehicle_id, sequence));"
    "CREATE INDEX IF NOT EXISTS patches_by_x ON patches(min_x, max_x);";

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// Adds `column` to the patches table of a file written before it existed; `fill` (SQL) sets it
// on the rows already there.
Status AddColumn(sqlite3* db, const std::string& path, const std::string& column,
                 const std::string& type, const std::string& fill) {
  Result<sqlite::Stmt> info = sqlite::Prepare(
      db, "SELECT 1 FROM pragma_table_info('patches') WHERE name = '" + column + "'");
  if (!info.ok()) return Internal(path + ": " + info.status().message());
  if (sqlite3_step(info->get()) == SQLITE_ROW) return Status::Ok();
  const std::string sql = "ALTER TABLE patches ADD COLUMN " + column + " " + type + ";" + fill;
  if (Status added = sqlite::Exec(db, sql.c_str()); !added.ok()) {
    return Internal(path + ": cannot add the " + column + " column: " + added.message());
  }
  return Status::Ok();
}

// Mosaic files written before patches could be refused, or before the server noted when it
// received each, lack those columns (their patches count as received now).
Status Migrate(sqlite3* db, const std::string& path) {
  FLEETLOC_RETURN_IF_ERROR(AddColumn(db, path, "refused_reason", "TEXT", ""));
  return AddColumn(db, path, "received", "REAL",
                   "UPDATE patches SET received = " + std::to_string(WallSeconds()) +
                       " WHERE received IS NULL;");
}

Status CheckPatch(const PatchRecord& p) {
  const std::string what = "patch " + p.vehicle_id + "#" + std::to_string(p.sequence) + ": field '";
  if (p.vehicle_id.empty()) return InvalidInput(what + "vehicle_id' is empty");
  if ((p.image.empty() || p.image.type() != CV_8UC1) && p.png.empty()) {
    return InvalidInput(what + "image' is not 8-bit gray");
  }
  if (!std::isfinite(p.pose.x) || !std::isfinite(p.pose.y) || !std::isfinite(p.pose.theta)) {
    return InvalidInput(what + "pose' is not finite");
  }
  if (const std::string problem = geometry::CovarianceProblem(p.covariance); !problem.empty()) {
    return InvalidInput(what + "covariance': " + problem);
  }
  if (!(p.quality >= 0 && p.quality <= 1)) return InvalidInput(what + "quality' is not in [0, 1]");
  if (!std::isfinite(p.stamp_s)) return InvalidInput(what + "stamp' is not finite");
  return Status::Ok();
}

Result<double> ReadResolution(sqlite3* db, const std::string& path) {
  Result<sqlite::Stmt> stmt =
      sqlite::Prepare(db, "SELECT value FROM metadata WHERE name = 'resolution'");
  if (!stmt.ok()) return InvalidInput(path + ": not a fleetloc mosaic (no metadata table)");
  if (sqlite3_step(stmt->get()) != SQLITE_ROW)
    return InvalidInput(path + ": no resolution in metadata");
  const double resolution = sqlite3_column_double(stmt->get(), 0);
  if (!(resolution > 0)) return InvalidInput(path + ": resolution in metadata is not positive");
  return resolution;
}

}  // namespace

PatchStore::PatchStore(std::string path, sqlite::Db db, double resolution_m)
    : path_(std::move(path)), db_(std::move(db)), resolution_m_(resolution_m) {}

Result<std::unique_ptr<PatchStore>> PatchStore::Open(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path + ": no such mosaic file");
  Result<sqlite::Db> db = sqlite::OpenDb(path, SQLITE_OPEN_READWRITE);
  if (!db.ok()) return db.status();
  sqlite3_busy_timeout(db->get(), kBusyTimeoutMs);
  Result<double> resolution = ReadResolution(db->get(), path);
  if (!resolution.ok()) return resolution.status();
  if (Status created = sqlite::Exec(db->get(), kSchema); !created.ok()) {
    return Internal(path + ": cannot create the patches table: " + created.message());
  }
  FLEETLOC_RETURN_IF_ERROR(Migrate(db->get(), path));
  return std::unique_ptr<PatchStore>(new PatchStore(path, std::move(db).value(), *resolution));
}

MapRect PatchStore::Footprint(const PatchRecord& p) const {
  // The decoded image's size, or the one its PNG header declares.
  const cv::Size size =
      !p.image.empty() ? p.image.size() : PngHeaderSize(p.png).value_or(cv::Size(0, 0));
  const double half_w = size.width * resolution_m_ / 2, half_h = size.height * resolution_m_ / 2;
  MapRect box{1e300, 1e300, -1e300, -1e300};
  for (const auto& [a, b] :
       {std::pair{half_h, half_w}, {half_h, -half_w}, {-half_h, half_w}, {-half_h, -half_w}}) {
    const Eigen::Vector2d m = p.pose * Eigen::Vector2d(a, b);
    box.x_min = std::min(box.x_min, m.x());
    box.x_max = std::max(box.x_max, m.x());
    box.y_min = std::min(box.y_min, m.y());
    box.y_max = std::max(box.y_max, m.y());
  }
  return box;
}

Result<PutOutcome> PatchStore::Put(const PatchRecord& p) {
  FLEETLOC_RETURN_IF_ERROR(CheckPatch(p));
  Result<std::vector<std::uint8_t>> png =
      p.png.empty() ? EncodeTile(p.image) : Result<std::vector<std::uint8_t>>(p.png);
  if (!png.ok()) return png.status();
  const MapRect box = Footprint(p);
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "INSERT OR IGNORE INTO patches(vehicle_id, sequence, stamp, x, y, theta, covariance, quality,"
      " min_x, min_y, max_x, max_y, image, received) "
      "VALUES(?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14)");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_stmt* s = stmt->get();
  sqlite3_bind_text(s, 1, p.vehicle_id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(s, 2, p.sequence);
  sqlite3_bind_double(s, 3, p.stamp_s);
  sqlite3_bind_double(s, 4, p.pose.x);
  sqlite3_bind_double(s, 5, p.pose.y);
  sqlite3_bind_double(s, 6, p.pose.theta);
  sqlite3_bind_blob(s, 7, p.covariance.data(), 9 * sizeof(double), SQLITE_TRANSIENT);
  sqlite3_bind_double(s, 8, p.quality);
  sqlite3_bind_double(s, 9, box.x_min);
  sqlite3_bind_double(s, 10, box.y_min);
  sqlite3_bind_double(s, 11, box.x_max);
  sqlite3_bind_double(s, 12, box.y_max);
  sqlite3_bind_blob(s, 13, png->data(), static_cast<int>(png->size()), SQLITE_STATIC);
  sqlite3_bind_double(s, 14, WallSeconds());
  if (sqlite3_step(s) != SQLITE_DONE) {
    return Internal(path_ + ": storing patch: " + sqlite::ErrorMessage(db_.get()));
  }
  return sqlite3_changes(db_.get()) == 1 ? PutOutcome::kStored : PutOutcome::kDuplicate;
}

namespace {

constexpr const char* kUnfoldedWhere =
    " FROM patches WHERE (folded_in_version = 0 OR folded_in_version > ?1) AND refused_reason IS "
    "NULL"
    " AND max_x > ?2 AND min_x < ?3 AND max_y > ?4 AND min_y < ?5 ORDER BY vehicle_id, sequence";

// Columns 0-7 of a patches row: vehicle_id, sequence, stamp, x, y, theta, covariance, quality.
PatchRecord ReadHeader(sqlite3_stmt* s) {
  PatchRecord p;
  p.vehicle_id = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
  p.sequence = sqlite3_column_int64(s, 1);
  p.stamp_s = sqlite3_column_double(s, 2);
  p.pose = {sqlite3_column_double(s, 3), sqlite3_column_double(s, 4), sqlite3_column_double(s, 5)};
  if (sqlite3_column_bytes(s, 6) == 9 * sizeof(double)) {
    std::memcpy(p.covariance.data(), sqlite3_column_blob(s, 6), 9 * sizeof(double));
  }
  p.quality = sqlite3_column_double(s, 7);
  return p;
}

Result<cv::Mat> DecodeColumn(sqlite3_stmt* s, int column) {
  const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, column));
  return DecodeGrayPng({blob, static_cast<size_t>(sqlite3_column_bytes(s, column))}, 1 << 15);
}

void BindRegion(sqlite3_stmt* s, const MapRect& r, int64_t committed_version) {
  sqlite3_bind_int64(s, 1, committed_version);
  sqlite3_bind_double(s, 2, r.x_min);
  sqlite3_bind_double(s, 3, r.x_max);
  sqlite3_bind_double(s, 4, r.y_min);
  sqlite3_bind_double(s, 5, r.y_max);
}

}  // namespace

Result<PatchQuery> PatchStore::Unfolded(const MapRect& r, int64_t committed_version) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      std::string("SELECT vehicle_id, sequence, stamp, x, y, theta, covariance, quality, image,"
                  " folded_in_version") +
          kUnfoldedWhere);
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_stmt* s = stmt->get();
  BindRegion(s, r, committed_version);
  PatchQuery query;
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    PatchRecord p = ReadHeader(s);
    Result<cv::Mat> image = DecodeColumn(s, 8);
    p.folded_in_version = sqlite3_column_int64(s, 9);
    if (!image.ok()) {
      ++query.unreadable;
      continue;
    }
    p.image = std::move(image).value();
    query.patches.push_back(std::move(p));
  }
  if (rc != SQLITE_DONE)
    return Internal(path_ + ": reading patches: " + sqlite::ErrorMessage(db_.get()));
  return query;
}

Result<std::vector<PatchRecord>> PatchStore::UnfoldedHeaders(const MapRect& r,
                                                             int64_t committed_version) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(), std::string("SELECT vehicle_id, sequence, stamp, x, y, theta, covariance, quality,"
                             " folded_in_version") +
                     kUnfoldedWhere);
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_stmt* s = stmt->get();
  BindRegion(s, r, committed_version);
  std::vector<PatchRecord> headers;
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    headers.push_back(ReadHeader(s));
    headers.back().folded_in_version = sqlite3_column_int64(s, 8);
  }
  if (rc != SQLITE_DONE)
    return Internal(path_ + ": reading patches: " + sqlite::ErrorMessage(db_.get()));
  return headers;
}

Result<cv::Mat> PatchStore::LoadImage(const std::string& vehicle_id, int64_t sequence) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(), "SELECT image FROM patches WHERE vehicle_id = ?1 AND sequence = ?2");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_bind_text(stmt->get(), 1, vehicle_id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(stmt->get(), 2, sequence);
  if (sqlite3_step(stmt->get()) != SQLITE_ROW) {
    return NotFound(path_ + ": patch " + vehicle_id + "#" + std::to_string(sequence) +
                    " is not stored");
  }
  Result<cv::Mat> image = DecodeColumn(stmt->get(), 0);
  if (!image.ok()) {
    return InvalidInput(path_ + ": patch " + vehicle_id + "#" + std::to_string(sequence) + ": " +
                        image.status().message());
  }
  return image;
}

Result<std::map<std::string, StoredUsage>> PatchStore::UsageByVehicle() {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "SELECT vehicle_id, COUNT(*), SUM(LENGTH(image)) FROM patches GROUP BY vehicle_id");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  std::map<std::string, StoredUsage> usage;
  int rc;
  while ((rc = sqlite3_step(stmt->get())) == SQLITE_ROW) {
    usage[reinterpret_cast<const char*>(sqlite3_column_text(stmt->get(), 0))] = {
        sqlite3_column_int64(stmt->get(), 1), sqlite3_column_int64(stmt->get(), 2)};
  }
  if (rc != SQLITE_DONE)
    return Internal(path_ + ": counting patches: " + sqlite::ErrorMessage(db_.get()));
  return usage;
}

Status PatchStore::MarkFolded(const std::vector<PatchRecord>& patches, int64_t version) {
  std::lock_guard lock(mutex_);
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db_.get(), "BEGIN IMMEDIATE"));
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "UPDATE patches SET folded_in_version = ?1 WHERE vehicle_id = ?2 AND sequence = ?3");
  bool ok = stmt.ok();
  for (size_t i = 0; ok && i < patches.size(); ++i) {
    sqlite::ScopedReset reset(stmt->get());
    sqlite3_bind_int64(stmt->get(), 1, version);
    sqlite3_bind_text(stmt->get(), 2, patches[i].vehicle_id.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(stmt->get(), 3, patches[i].sequence);
    ok = sqlite3_step(stmt->get()) == SQLITE_DONE;
  }
  if (!ok) {
    const std::string message = sqlite::ErrorMessage(db_.get());
    (void)sqlite::Exec(db_.get(), "ROLLBACK");
    return Internal(path_ + ": marking patches folded: " + message);
  }
  return sqlite::Exec(db_.get(), "COMMIT");
}

Status PatchStore::MarkRefused(const std::vector<Refusal>& refusals) {
  std::lock_guard lock(mutex_);
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db_.get(), "BEGIN IMMEDIATE"));
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(), "UPDATE patches SET refused_reason = ?1 WHERE vehicle_id = ?2 AND sequence = ?3");
  bool ok = stmt.ok();
  for (size_t i = 0; ok && i < refusals.size(); ++i) {
    sqlite::ScopedReset reset(stmt->get());
    sqlite3_bind_text(stmt->get(), 1, refusals[i].reason.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(stmt->get(), 2, refusals[i].vehicle_id.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(stmt->get(), 3, refusals[i].sequence);
    ok = sqlite3_step(stmt->get()) == SQLITE_DONE;
  }
  if (!ok) {
    const std::string message = sqlite::ErrorMessage(db_.get());
    (void)sqlite::Exec(db_.get(), "ROLLBACK");
    return Internal(path_ + ": marking patches refused: " + message);
  }
  return sqlite::Exec(db_.get(), "COMMIT");
}

Status PatchStore::ClearUncommittedMarks(int64_t committed_version) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(), "UPDATE patches SET folded_in_version = 0 WHERE folded_in_version > ?1");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_bind_int64(stmt->get(), 1, committed_version);
  if (sqlite3_step(stmt->get()) != SQLITE_DONE) {
    return Internal(path_ + ": clearing patch marks: " + sqlite::ErrorMessage(db_.get()));
  }
  return Status::Ok();
}

Result<PatchCounts> PatchStore::Counts(int64_t committed_version) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt =
      sqlite::Prepare(db_.get(),
                      "SELECT COUNT(*), SUM(folded_in_version > 0 AND folded_in_version <= ?1),"
                      " SUM(refused_reason IS NOT NULL) FROM patches");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_bind_int64(stmt->get(), 1, committed_version);
  if (sqlite3_step(stmt->get()) != SQLITE_ROW) {
    return Internal(path_ + ": counting patches: " + sqlite::ErrorMessage(db_.get()));
  }
  return PatchCounts{sqlite3_column_int64(stmt->get(), 0), sqlite3_column_int64(stmt->get(), 1),
                     sqlite3_column_int64(stmt->get(), 2)};
}

}  // namespace fleetloc::mosaic
