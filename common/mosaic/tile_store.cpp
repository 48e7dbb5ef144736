// SQLite tile store.
#include "mosaic/tile_store.h"

#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <utility>

#include "mosaic/tile_codec.h"

namespace fleetloc::mosaic {
namespace {

constexpr int kBusyTimeoutMs = 5000;

constexpr char kSchema[] =
    "CREATE TABLE metadata(name TEXT PRIMARY KEY, value TEXT);"
    "CREATE TABLE tiles(level INTEGER, col INTEGER, row INTEGER, version INTEGER, data BLOB,"
    " PRIMARY KEY(level, col, row, version));";

// The newest version <= ?4 of one tile: a search of the primary key's index (TileLookupPlan).
constexpr char kSelectTileSql[] =
    "SELECT data FROM tiles WHERE level = ?1 AND col = ?2 AND row = ?3 AND version <= ?4"
    " ORDER BY version DESC LIMIT 1";

Status StepDone(sqlite3_stmt* stmt, const std::string& what) {
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_DONE) return Status::Ok();
  return Internal(what + ": " + sqlite3_errmsg(sqlite3_db_handle(stmt)));
}

Status InsertMetadata(sqlite3* db, const Metadata& metadata) {
  Result<sqlite::Stmt> insert =
      sqlite::Prepare(db, "INSERT OR REPLACE INTO metadata(name, value) VALUES(?1, ?2)");
  if (!insert.ok()) return insert.status();
  for (const auto& [name, value] : metadata) {
    sqlite::ScopedReset reset(insert->get());
    sqlite3_bind_text(insert->get(), 1, name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(insert->get(), 2, value.c_str(), -1, SQLITE_TRANSIENT);
    FLEETLOC_RETURN_IF_ERROR(StepDone(insert->get(), "writing metadata '" + name + "'"));
  }
  return Status::Ok();
}

// Sets WAL mode and writes the schema and the metadata of `layout` in one transaction.
Status InitializeFile(sqlite3* db, const MosaicLayout& layout) {
  sqlite3_busy_timeout(db, kBusyTimeoutMs);
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db, "PRAGMA journal_mode=WAL; BEGIN"));
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db, kSchema));
  FLEETLOC_RETURN_IF_ERROR(InsertMetadata(db, LayoutToMetadata(layout, IsoTimeNowUtc())));
  return sqlite::Exec(db, "COMMIT");
}

std::string ColumnText(sqlite3_stmt* stmt, int column) {
  const unsigned char* text = sqlite3_column_text(stmt, column);
  return text ? reinterpret_cast<const char*>(text) : "";
}

// A SQLite file is always a whole number of pages; SQLite itself only notices truncation by whole
// pages, so a file cut inside its last page is caught here.
Status CheckWholePages(sqlite3* db, const std::string& path) {
  Result<sqlite::Stmt> pragma = sqlite::Prepare(db, "PRAGMA page_size");
  if (!pragma.ok()) return pragma.status();
  if (sqlite3_step(pragma->get()) != SQLITE_ROW) return Internal(sqlite3_errmsg(db));
  const std::uintmax_t page_size = sqlite3_column_int64(pragma->get(), 0);
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  if (ec || page_size == 0 || file_size % page_size != 0) {
    return InvalidInput("file size " + std::to_string(file_size) +
                        " is not a whole number of pages (truncated?)");
  }
  return Status::Ok();
}

}  // namespace

TileStore::TileStore(std::string path, sqlite::Db db, OpenMode mode)
    : path_(std::move(path)), mode_(mode), db_(std::move(db)) {}

TileStore::~TileStore() {
  if (pending_version_ >= 0) (void)sqlite::Exec(db_.get(), "ROLLBACK");
}

Result<std::unique_ptr<TileStore>> TileStore::Create(const std::string& path, MosaicLayout layout) {
  if (layout.mosaic_id.empty()) layout.mosaic_id = NewMosaicId();
  layout.version = 0;
  if (Status valid = ValidateLayout(layout); !valid.ok()) {
    return InvalidInput(path + ": " + valid.message());
  }
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) return InvalidInput(path + ": already exists");
  Result<sqlite::Db> db = sqlite::OpenDb(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  if (!db.ok()) return db.status();
  if (Status created = InitializeFile(db->get(), layout); !created.ok()) {
    db->reset();  // close before removing
    sqlite::RemoveDatabaseFiles(path);
    return Internal(path + ": cannot create mosaic: " + created.message());
  }
  std::unique_ptr<TileStore> store(
      new TileStore(path, std::move(db).value(), OpenMode::kReadWrite));
  FLEETLOC_RETURN_IF_ERROR(store->Init(path + ": cannot create mosaic: "));
  return store;
}

Result<std::unique_ptr<TileStore>> TileStore::Open(const std::string& path, OpenMode mode) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return NotFound(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) {
    return InvalidInput(path + ": not a fleetloc mosaic (not a regular file)");
  }
  // A reader of a writable file still opens it read-write with SQLite's query_only guard: only a
  // read-write connection can fold and delete the WAL side files when it is the last to close.
  const bool writable = ::access(path.c_str(), W_OK) == 0;
  const bool query_only = mode == OpenMode::kReadOnly;
  const int flags = query_only && !writable ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
  Result<sqlite::Db> db = sqlite::OpenDb(path, flags);
  if (!db.ok()) return db.status();
  sqlite3_busy_timeout(db->get(), kBusyTimeoutMs);
  if (query_only) FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db->get(), "PRAGMA query_only = 1"));
  std::unique_ptr<TileStore> store(new TileStore(path, std::move(db).value(), mode));
  FLEETLOC_RETURN_IF_ERROR(store->Init(path + ": not a fleetloc mosaic: "));
  return store;
}

// Reads and validates the metadata and prepares the reused statements. Any failure means the file
// is not a usable mosaic: InvalidInput prefixed with `problem_prefix`.
Status TileStore::Init(const std::string& problem_prefix) {
  std::lock_guard lock(mutex_);
  Result<Metadata> metadata = ReadMetadataLocked();
  if (!metadata.ok()) return InvalidInput(problem_prefix + metadata.status().message());
  if (Status whole = CheckWholePages(db_.get(), path_); !whole.ok()) {
    return InvalidInput(problem_prefix + whole.message());
  }
  Result<MosaicLayout> layout = LayoutFromMetadata(*metadata);
  if (!layout.ok()) return InvalidInput(problem_prefix + layout.status().message());
  layout_ = std::move(layout).value();
  const std::pair<sqlite::Stmt*, const char*> statements[] = {
      {&select_tile_, kSelectTileSql},
      {&insert_tile_,
       "INSERT OR REPLACE INTO tiles(level, col, row, version, data) VALUES(?1, ?2, ?3, ?4, ?5)"},
      {&select_version_, "SELECT value FROM metadata WHERE name = 'version'"},
      {&update_version_, "UPDATE metadata SET value = ?1 WHERE name = 'version'"}};
  for (const auto& [stmt, sql] : statements) {
    Result<sqlite::Stmt> prepared = sqlite::Prepare(db_.get(), sql);
    if (!prepared.ok()) {
      return InvalidInput(problem_prefix + "tiles table: " + prepared.status().message());
    }
    *stmt = std::move(prepared).value();
  }
  return Status::Ok();
}

MosaicLayout TileStore::layout() const {
  std::lock_guard lock(mutex_);
  return layout_;
}

long long TileStore::version() const {
  std::lock_guard lock(mutex_);
  return layout_.version;
}

Result<std::vector<std::uint8_t>> TileStore::ReadTileBytes(const TileKey& key) {
  return ReadTileBytesAt(key, version());
}

Result<std::vector<std::uint8_t>> TileStore::ReadTileBytesAt(const TileKey& key,
                                                             long long version) {
  std::lock_guard lock(mutex_);
  sqlite3_stmt* stmt = select_tile_.get();
  sqlite::ScopedReset reset(stmt);
  sqlite3_bind_int(stmt, 1, key.level);
  sqlite3_bind_int(stmt, 2, key.col);
  sqlite3_bind_int(stmt, 3, key.row);
  sqlite3_bind_int64(stmt, 4, std::min(version, layout_.version));
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_DONE) return NotFound(path_ + ": no tile " + ToString(key));
  if (rc != SQLITE_ROW) {
    return Internal(path_ + ": reading tile " + ToString(key) + ": " +
                    sqlite::ErrorMessage(db_.get()));
  }
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt, 0));
  const int size = sqlite3_column_bytes(stmt, 0);
  return std::vector<std::uint8_t>(data, data + size);
}

Result<std::vector<TileKey>> TileStore::TilesChangedAfter(long long version) {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> select = sqlite::Prepare(
      db_.get(),
      "SELECT DISTINCT level, col, row FROM tiles WHERE version > ?1 AND version <= ?2"
      " ORDER BY level, col, row");
  if (!select.ok()) return select.status();
  sqlite3_bind_int64(select->get(), 1, version);
  sqlite3_bind_int64(select->get(), 2, layout_.version);
  std::vector<TileKey> keys;
  int rc;
  while ((rc = sqlite3_step(select->get())) == SQLITE_ROW) {
    keys.push_back({sqlite3_column_int(select->get(), 0), sqlite3_column_int(select->get(), 1),
                    sqlite3_column_int(select->get(), 2)});
  }
  if (rc != SQLITE_DONE) {
    return Internal(path_ + ": listing changed tiles: " + sqlite::ErrorMessage(db_.get()));
  }
  return keys;
}

Result<cv::Mat> TileStore::ReadTile(const TileKey& key) {
  Result<std::vector<std::uint8_t>> bytes = ReadTileBytes(key);
  if (!bytes.ok()) return bytes.status();
  Result<cv::Mat> tile = DecodeTile(*bytes, layout_.tile_size_px);  // tile size never changes
  if (!tile.ok()) {
    return InvalidInput(path_ + ": tile " + ToString(key) + ": " + tile.status().message());
  }
  return tile;
}

Status TileStore::BeginVersion() {
  std::lock_guard lock(mutex_);
  FLEETLOC_CHECK(pending_version_ < 0);
  if (mode_ == OpenMode::kReadOnly) return InvalidInput(path_ + ": opened read-only");
  if (Status begun = sqlite::Exec(db_.get(), "BEGIN IMMEDIATE"); !begun.ok()) {
    return Internal(path_ + ": cannot start a new version: " + begun.message());
  }
  Result<long long> committed = ReadCommittedVersionLocked();  // another writer may have committed
  if (!committed.ok()) {
    (void)sqlite::Exec(db_.get(), "ROLLBACK");
    return committed.status();
  }
  layout_.version = *committed;
  pending_version_ = *committed + 1;
  return Status::Ok();
}

Status TileStore::PutTile(const TileKey& key, const cv::Mat& tile) {
  const int t = layout_.tile_size_px;
  if (tile.type() != CV_8UC1 || tile.rows != t || tile.cols != t) {
    return InvalidInput(path_ + ": tile " + ToString(key) + " must be 8-bit gray " +
                        std::to_string(t) + "x" + std::to_string(t));
  }
  Result<std::vector<std::uint8_t>> png = EncodeTile(tile);
  if (!png.ok()) return png.status();
  return PutTileBytes(key, *png);
}

Status TileStore::PutTileBytes(const TileKey& key, std::span<const std::uint8_t> png) {
  std::lock_guard lock(mutex_);
  FLEETLOC_CHECK(pending_version_ >= 0);
  FLEETLOC_RETURN_IF_ERROR(CheckKey(key));
  sqlite3_stmt* stmt = insert_tile_.get();
  sqlite::ScopedReset reset(stmt);
  sqlite3_bind_int(stmt, 1, key.level);
  sqlite3_bind_int(stmt, 2, key.col);
  sqlite3_bind_int(stmt, 3, key.row);
  sqlite3_bind_int64(stmt, 4, pending_version_);
  sqlite3_bind_blob(stmt, 5, png.data(), static_cast<int>(png.size()), SQLITE_STATIC);
  return StepDone(stmt, path_ + ": writing tile " + ToString(key));
}

Result<long long> TileStore::CommitVersion() {
  std::lock_guard lock(mutex_);
  FLEETLOC_CHECK(pending_version_ >= 0);
  const long long next = pending_version_;
  pending_version_ = -1;
  Status committed;
  {
    sqlite::ScopedReset reset(update_version_.get());
    sqlite3_bind_text(update_version_.get(), 1, std::to_string(next).c_str(), -1, SQLITE_TRANSIENT);
    committed = StepDone(update_version_.get(), path_ + ": writing version");
  }
  if (committed.ok()) committed = sqlite::Exec(db_.get(), "COMMIT");
  if (!committed.ok()) {
    (void)sqlite::Exec(db_.get(), "ROLLBACK");
    return Internal(path_ + ": version " + std::to_string(next) +
                    " not committed: " + committed.message());
  }
  layout_.version = next;
  return next;
}

Status TileStore::AbortVersion() {
  std::lock_guard lock(mutex_);
  FLEETLOC_CHECK(pending_version_ >= 0);
  pending_version_ = -1;
  return sqlite::Exec(db_.get(), "ROLLBACK");
}

Result<long long> TileStore::Refresh() {
  std::lock_guard lock(mutex_);
  Result<long long> committed = ReadCommittedVersionLocked();
  if (committed.ok() && pending_version_ < 0) layout_.version = *committed;
  return committed;
}

Result<long long> TileStore::ReadCommittedVersionLocked() {
  sqlite3_stmt* stmt = select_version_.get();
  sqlite::ScopedReset reset(stmt);
  if (sqlite3_step(stmt) != SQLITE_ROW) {
    return Internal(path_ + ": cannot read the mosaic version: " + sqlite::ErrorMessage(db_.get()));
  }
  const std::string text = ColumnText(stmt, 0);
  long long version = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), version);
  if (ec != std::errc() || end != text.data() + text.size() || version < 0) {
    return InvalidInput(path_ + ": metadata 'version' = '" + text + "' is not a version number");
  }
  return version;
}

Status TileStore::CheckKey(const TileKey& key) const {
  const bool inside = key.level >= 0 && key.level < layout_.levels && key.col >= 0 &&
                      key.row >= 0 && key.col < TileColumns(layout_, key.level) &&
                      key.row < TileRows(layout_, key.level);
  if (inside) return Status::Ok();
  return InvalidInput(path_ + ": tile " + ToString(key) + " is outside the mosaic's tile grid");
}

Result<Metadata> TileStore::ReadMetadata() {
  std::lock_guard lock(mutex_);
  return ReadMetadataLocked();
}

Result<Metadata> TileStore::ReadMetadataLocked() {
  Result<sqlite::Stmt> select = sqlite::Prepare(db_.get(), "SELECT name, value FROM metadata");
  if (!select.ok()) return select.status();
  Metadata metadata;
  int rc;
  while ((rc = sqlite3_step(select->get())) == SQLITE_ROW) {
    metadata[ColumnText(select->get(), 0)] = ColumnText(select->get(), 1);
  }
  if (rc != SQLITE_DONE) return Internal(sqlite::ErrorMessage(db_.get()));
  return metadata;
}

Result<std::vector<long long>> TileStore::TileCountsPerLevel() {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> count =
      sqlite::Prepare(db_.get(),
                      "SELECT level, COUNT(*) FROM (SELECT DISTINCT level, col, row FROM tiles"
                      " WHERE version <= ?1) GROUP BY level");
  if (!count.ok()) return Internal(path_ + ": " + count.status().message());
  sqlite3_bind_int64(count->get(), 1, layout_.version);
  std::vector<long long> counts(layout_.levels, 0);
  int rc;
  while ((rc = sqlite3_step(count->get())) == SQLITE_ROW) {
    const int level = sqlite3_column_int(count->get(), 0);
    if (level >= 0 && level < layout_.levels) counts[level] = sqlite3_column_int64(count->get(), 1);
  }
  if (rc != SQLITE_DONE) return Internal(path_ + ": " + sqlite::ErrorMessage(db_.get()));
  return counts;
}

Result<std::string> TileStore::TileLookupPlan() {
  std::lock_guard lock(mutex_);
  Result<sqlite::Stmt> explain =
      sqlite::Prepare(db_.get(), std::string("EXPLAIN QUERY PLAN ") + kSelectTileSql);
  if (!explain.ok()) return Internal(path_ + ": " + explain.status().message());
  std::string plan;
  int rc;
  while ((rc = sqlite3_step(explain->get())) == SQLITE_ROW) {
    plan += (plan.empty() ? "" : "; ") + ColumnText(explain->get(), 3);  // id, parent, 0, detail
  }
  if (rc != SQLITE_DONE) return Internal(path_ + ": " + sqlite::ErrorMessage(db_.get()));
  return plan;
}

TileLoader MakeTileLoader(std::shared_ptr<TileStore> store) {
  FLEETLOC_CHECK(store != nullptr);
  return [store = std::move(store)](const TileKey& key) { return store->ReadTile(key); };
}

}  // namespace fleetloc::mosaic
