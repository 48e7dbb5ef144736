// The patches table in the mosaic file.
#include "mosaic/patch_store.h"

#include <sqlite3.h>

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
    " refused_reason TEXT, PRIMARY KEY(vehicle_id, sequence));"
    "CREATE INDEX IF NOT EXISTS patches_by_x ON patches(min_x, max_x);";

// Mosaic files written before patches could be refused lack the column: add it.
Status AddRefusedColumn(sqlite3* db, const std::string& path) {
  Result<sqlite::Stmt> info = sqlite::Prepare(db, "SELECT 1 FROM pragma_table_info('patches') WHERE name = 'refused_reason'");
  if (!info.ok()) return Internal(path + ": " + info.status().message());
  if (sqlite3_step(info->get()) == SQLITE_ROW) return Status::Ok();
  if (Status added = sqlite::Exec(db, "ALTER TABLE patches ADD COLUMN refused_reason TEXT"); !added.ok()) {
    return Internal(path + ": cannot add the refused_reason column: " + added.message());
  }
  return Status::Ok();
}

Status CheckPatch(const PatchRecord& p) {
  const std::string what = "patch " + p.vehicle_id + "#" + std::to_string(p.sequence) + ": field '";
  if (p.vehicle_id.empty()) return InvalidInput(what + "vehicle_id' is empty");
  if (p.image.empty() || p.image.type() != CV_8UC1) return InvalidInput(what + "image' is not 8-bit gray");
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
  Result<sqlite::Stmt> stmt = sqlite::Prepare(db, "SELECT value FROM metadata WHERE name = 'resolution'");
  if (!stmt.ok()) return InvalidInput(path + ": not a fleetloc mosaic (no metadata table)");
  if (sqlite3_step(stmt->get()) != SQLITE_ROW) return InvalidInput(path + ": no resolution in metadata");
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
  FLEETLOC_RETURN_IF_ERROR(AddRefusedColumn(db->get(), path));
  return std::unique_ptr<PatchStore>(new PatchStore(path, std::move(db).value(), *resolution));
}

MapRect PatchStore::Footprint(const PatchRecord& p) const {
  const double half_w = p.image.cols * resolution_m_ / 2, half_h = p.image.rows * resolution_m_ / 2;
  MapRect box{1e300, 1e300, -1e300, -1e300};
  for (const auto& [a, b] : {std::pair{half_h, half_w}, {half_h, -half_w}, {-half_h, half_w},
                             {-half_h, -half_w}}) {
    const Eigen::Vector2d m = p.pose * Eigen::Vector2d(a, b);
    box.x_min = std::min(box.x_min, m.x()), box.x_max = std::max(box.x_max, m.x());
    box.y_min = std::min(box.y_min, m.y()), box.y_max = std::max(box.y_max, m.y());
  }
  return box;
}

Result<PutOutcome> PatchStore::Put(const PatchRecord& p) {
  FLEETLOC_RETURN_IF_ERROR(CheckPatch(p));
  Result<std::vector<std::uint8_t>> png = EncodeTile(p.image);
  if (!png.ok()) return png.status();
  const MapRect box = Footprint(p);
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "INSERT OR IGNORE INTO patches(vehicle_id, sequence, stamp, x, y, theta, covariance, quality,"
      " min_x, min_y, max_x, max_y, image) VALUES(?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13)");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_stmt* s = stmt->get();
  sqlite3_bind_text(s, 1, p.vehicle_id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(s, 2, p.sequence);
  sqlite3_bind_double(s, 3, p.stamp_s);
  sqlite3_bind_double(s, 4, p.pose.x), sqlite3_bind_double(s, 5, p.pose.y);
  sqlite3_bind_double(s, 6, p.pose.theta);
  sqlite3_bind_blob(s, 7, p.covariance.data(), 9 * sizeof(double), SQLITE_TRANSIENT);
  sqlite3_bind_double(s, 8, p.quality);
  sqlite3_bind_double(s, 9, box.x_min), sqlite3_bind_double(s, 10, box.y_min);
  sqlite3_bind_double(s, 11, box.x_max), sqlite3_bind_double(s, 12, box.y_max);
  sqlite3_bind_blob(s, 13, png->data(), static_cast<int>(png->size()), SQLITE_STATIC);
  if (sqlite3_step(s) != SQLITE_DONE) {
    return Internal(path_ + ": storing patch: " + sqlite::ErrorMessage(db_.get()));
  }
  return sqlite3_changes(db_.get()) == 1 ? PutOutcome::kStored : PutOutcome::kDuplicate;
}

Result<PatchQuery> PatchStore::Unfolded(const MapRect& r, int64_t committed_version) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
      "SELECT vehicle_id, sequence, stamp, x, y, theta, covariance, quality, image,"
      " folded_in_version FROM patches WHERE (folded_in_version = 0 OR folded_in_version > ?1)"
      " AND refused_reason IS NULL"
      " AND max_x > ?2 AND min_x < ?3 AND max_y > ?4 AND min_y < ?5"
      " ORDER BY vehicle_id, sequence");
  if (!stmt.ok()) return Internal(path_ + ": " + stmt.status().message());
  sqlite3_stmt* s = stmt->get();
  sqlite3_bind_int64(s, 1, committed_version);
  sqlite3_bind_double(s, 2, r.x_min), sqlite3_bind_double(s, 3, r.x_max);
  sqlite3_bind_double(s, 4, r.y_min), sqlite3_bind_double(s, 5, r.y_max);
  PatchQuery query;
  int rc;
  while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
    PatchRecord p;
    p.vehicle_id = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    p.sequence = sqlite3_column_int64(s, 1);
    p.stamp_s = sqlite3_column_double(s, 2);
    p.pose = {sqlite3_column_double(s, 3), sqlite3_column_double(s, 4), sqlite3_column_double(s, 5)};
    if (sqlite3_column_bytes(s, 6) == 9 * sizeof(double)) {
      std::memcpy(p.covariance.data(), sqlite3_column_blob(s, 6), 9 * sizeof(double));
    }
    p.quality = sqlite3_column_double(s, 7);
    const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, 8));
    Result<cv::Mat> image =
        DecodeGrayPng({blob, static_cast<size_t>(sqlite3_column_bytes(s, 8))}, 1 << 15);
    p.folded_in_version = sqlite3_column_int64(s, 9);
    if (!image.ok()) {
      ++query.unreadable;
      continue;
    }
    p.image = std::move(image).value();
    query.patches.push_back(std::move(p));
  }
  if (rc != SQLITE_DONE) return Internal(path_ + ": reading patches: " + sqlite::ErrorMessage(db_.get()));
  return query;
}

Status PatchStore::MarkFolded(const std::vector<PatchRecord>& patches, int64_t version) {
  std::lock_guard lock(mutex_);
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db_.get(), "BEGIN IMMEDIATE"));
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(), "UPDATE patches SET folded_in_version = ?1 WHERE vehicle_id = ?2 AND sequence = ?3");
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
  Result<sqlite::Stmt> stmt = sqlite::Prepare(
      db_.get(),
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
