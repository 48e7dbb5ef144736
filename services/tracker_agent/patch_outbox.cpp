// SQLite-backed patch outbox.
#include "tracker_agent/patch_outbox.h"

#include <spdlog/spdlog.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>

namespace fleetloc::tracker_agent {
namespace {

constexpr const char* kSchema =
    "PRAGMA journal_mode=WAL;"
    "CREATE TABLE IF NOT EXISTS meta(name TEXT PRIMARY KEY, value INTEGER NOT NULL);"
    "INSERT OR IGNORE INTO meta(name, value) VALUES('next_sequence', 1);"
    "INSERT OR IGNORE INTO meta(name, value) VALUES('dropped', 0);"
    "CREATE TABLE IF NOT EXISTS outbox(sequence INTEGER PRIMARY KEY, stamp REAL, mosaic_id TEXT,"
    " mosaic_version INTEGER, x REAL, y REAL, theta REAL, covariance BLOB, quality REAL,"
    " resolution REAL, png BLOB NOT NULL, last_sent REAL NOT NULL DEFAULT -1,"
    " sent_boot TEXT NOT NULL DEFAULT '');"
    "CREATE TABLE IF NOT EXISTS acks(sequence INTEGER NOT NULL, server_id TEXT NOT NULL,"
    " PRIMARY KEY(sequence, server_id)) WITHOUT ROWID;";

// The patch to drop when the outbox is full: of its oldest tenth (at least one), the one of
// lowest quality (the oldest of those).
constexpr const char* kVictim =
    "SELECT sequence FROM (SELECT sequence, quality FROM outbox ORDER BY sequence LIMIT"
    " MAX(1, (SELECT COUNT(*) FROM outbox) / 10)) ORDER BY quality ASC, sequence ASC LIMIT 1";

// Outboxes written before sends were tied to a boot lack sent_boot: their patches are due at once.
Status AddSentBoot(sqlite3* db, const std::string& path) {
  auto info =
      sqlite::Prepare(db, "SELECT 1 FROM pragma_table_info('outbox') WHERE name = 'sent_boot'");
  if (!info.ok()) return Internal(path + ": " + info.status().message());
  if (sqlite3_step(info->get()) == SQLITE_ROW) return Status::Ok();
  if (Status s =
          sqlite::Exec(db, "ALTER TABLE outbox ADD COLUMN sent_boot TEXT NOT NULL DEFAULT ''");
      !s.ok()) {
    return Internal(path + ": cannot add the sent_boot column: " + s.message());
  }
  return Status::Ok();
}

}  // namespace

OutboxTime OutboxNow() {
  std::string boot;
  std::getline(std::ifstream("/proc/sys/kernel/random/boot_id"), boot);
  const double monotonic =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  return {boot, monotonic};
}

Result<std::unique_ptr<PatchOutbox>> PatchOutbox::Open(const std::string& path,
                                                       OutboxLimits limits) {
  Result<sqlite::Db> db = sqlite::OpenDb(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  if (!db.ok()) return db.status();
  sqlite3_busy_timeout(db->get(), 5000);
  std::unique_ptr<PatchOutbox> outbox(new PatchOutbox(path, std::move(db).value(), limits));
  FLEETLOC_RETURN_IF_ERROR(outbox->Exec("create the outbox", kSchema));
  FLEETLOC_RETURN_IF_ERROR(AddSentBoot(outbox->db_.get(), path));
  return outbox;
}

Status PatchOutbox::Exec(const std::string& what, const char* sql) {
  if (Status s = sqlite::Exec(db_.get(), sql); !s.ok()) {
    return Internal(path_ + ": cannot " + what + ": " + s.message());
  }
  return Status::Ok();
}

Result<uint64_t> PatchOutbox::Add(transport::PatchToSend* p) {
  std::lock_guard lock(mutex_);
  FLEETLOC_RETURN_IF_ERROR(Exec("begin", "BEGIN IMMEDIATE"));
  auto fail = [&](const std::string& what) -> Status {
    const std::string message = sqlite::ErrorMessage(db_.get());
    (void)sqlite::Exec(db_.get(), "ROLLBACK");
    return Internal(path_ + ": " + what + ": " + message);
  };
  auto next = sqlite::Prepare(db_.get(), "SELECT value FROM meta WHERE name = 'next_sequence'");
  if (!next.ok() || sqlite3_step(next->get()) != SQLITE_ROW) return fail("reading the sequence");
  p->sequence = static_cast<uint64_t>(sqlite3_column_int64(next->get(), 0));
  auto insert = sqlite::Prepare(
      db_.get(),
      "INSERT INTO outbox(sequence, stamp, mosaic_id, mosaic_version, x, y, theta, covariance,"
      " quality, resolution, png) VALUES(?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11)");
  if (!insert.ok()) return fail("preparing");
  sqlite3_stmt* s = insert->get();
  sqlite3_bind_int64(s, 1, static_cast<sqlite3_int64>(p->sequence));
  sqlite3_bind_double(s, 2, p->stamp_s);
  sqlite3_bind_text(s, 3, p->mosaic_id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int64(s, 4, p->mosaic_version);
  sqlite3_bind_double(s, 5, p->pose.x);
  sqlite3_bind_double(s, 6, p->pose.y);
  sqlite3_bind_double(s, 7, p->pose.theta);
  sqlite3_bind_blob(s, 8, p->covariance, sizeof p->covariance, SQLITE_TRANSIENT);
  sqlite3_bind_double(s, 9, p->quality);
  sqlite3_bind_double(s, 10, p->resolution_m);
  sqlite3_bind_blob(s, 11, p->png.data(), static_cast<int>(p->png.size()), SQLITE_STATIC);
  if (sqlite3_step(s) != SQLITE_DONE) return fail("storing the patch");
  if (!sqlite::Exec(db_.get(), "UPDATE meta SET value = value + 1 WHERE name = 'next_sequence'")
           .ok()) {
    return fail("advancing the sequence");
  }
  Result<long long> dropped = EnforceLimitsLocked();
  if (!dropped.ok()) return fail("keeping the outbox within its limits");
  FLEETLOC_RETURN_IF_ERROR(Exec("commit", "COMMIT"));
  if (*dropped > 0) {
    spdlog::warn("{}: outbox full ({} patches, {} MB at most): {} patch(es) dropped", path_,
                 limits_.max_patches, limits_.max_bytes >> 20, *dropped);
  }
  return p->sequence;
}

Result<long long> PatchOutbox::EnforceLimitsLocked() {
  long long dropped = 0;
  for (;;) {
    auto totals = sqlite::Prepare(db_.get(), "SELECT COUNT(*), TOTAL(LENGTH(png)) FROM outbox");
    if (!totals.ok() || sqlite3_step(totals->get()) != SQLITE_ROW)
      return Internal("counting the outbox");
    const long long count = sqlite3_column_int64(totals->get(), 0);
    const auto bytes = static_cast<long long>(sqlite3_column_double(totals->get(), 1));
    if (count <= limits_.max_patches && bytes <= limits_.max_bytes) break;
    auto victim = sqlite::Prepare(db_.get(), kVictim);
    if (!victim.ok() || sqlite3_step(victim->get()) != SQLITE_ROW)
      return Internal("choosing a patch to drop");
    FLEETLOC_RETURN_IF_ERROR(
        RemoveLocked(static_cast<uint64_t>(sqlite3_column_int64(victim->get(), 0))));
    ++dropped;
  }
  if (dropped > 0) {
    auto count =
        sqlite::Prepare(db_.get(), "UPDATE meta SET value = value + ?1 WHERE name = 'dropped'");
    if (!count.ok()) return count.status();
    sqlite3_bind_int64(count->get(), 1, dropped);
    if (sqlite3_step(count->get()) != SQLITE_DONE) return Internal("counting dropped patches");
  }
  return dropped;
}

Result<std::vector<transport::PatchToSend>> PatchOutbox::Due(const OutboxTime& now,
                                                             double retry_after_s, int max) {
  std::lock_guard lock(mutex_);
  auto select = sqlite::Prepare(
      db_.get(),
      "SELECT sequence, stamp, mosaic_id, mosaic_version, x, y, theta, covariance, quality,"
      " resolution, png FROM outbox WHERE last_sent < 0 OR sent_boot != ?3 OR last_sent < ?1"
      " ORDER BY sequence LIMIT ?2");
  if (!select.ok()) return Internal(path_ + ": " + select.status().message());
  sqlite3_stmt* s = select->get();
  sqlite3_bind_double(s, 1, now.monotonic_s - retry_after_s);
  sqlite3_bind_int(s, 2, max);
  sqlite3_bind_text(s, 3, now.boot_id.c_str(), -1, SQLITE_TRANSIENT);
  std::vector<transport::PatchToSend> due;
  while (sqlite3_step(s) == SQLITE_ROW) {
    transport::PatchToSend p;
    p.sequence = static_cast<uint64_t>(sqlite3_column_int64(s, 0));
    p.stamp_s = sqlite3_column_double(s, 1);
    p.mosaic_id = reinterpret_cast<const char*>(sqlite3_column_text(s, 2));
    p.mosaic_version = sqlite3_column_int64(s, 3);
    p.pose = {sqlite3_column_double(s, 4), sqlite3_column_double(s, 5),
              sqlite3_column_double(s, 6)};
    if (sqlite3_column_bytes(s, 7) == sizeof p.covariance) {
      std::memcpy(p.covariance, sqlite3_column_blob(s, 7), sizeof p.covariance);
    }
    p.quality = static_cast<float>(sqlite3_column_double(s, 8));
    p.resolution_m = sqlite3_column_double(s, 9);
    const auto* png = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, 10));
    p.png.assign(png, png + sqlite3_column_bytes(s, 10));
    due.push_back(std::move(p));
  }
  return due;
}

Status PatchOutbox::MarkSent(uint64_t sequence, const OutboxTime& now) {
  std::lock_guard lock(mutex_);
  auto update = sqlite::Prepare(
      db_.get(), "UPDATE outbox SET last_sent = ?1, sent_boot = ?3 WHERE sequence = ?2");
  if (!update.ok()) return Internal(path_ + ": " + update.status().message());
  sqlite3_bind_double(update->get(), 1, now.monotonic_s);
  sqlite3_bind_int64(update->get(), 2, static_cast<sqlite3_int64>(sequence));
  sqlite3_bind_text(update->get(), 3, now.boot_id.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(update->get()) != SQLITE_DONE)
    return Internal(path_ + ": " + sqlite::ErrorMessage(db_.get()));
  return Status::Ok();
}

Result<bool> PatchOutbox::Acknowledge(uint64_t sequence, const std::string& server_id,
                                      const std::vector<std::string>& required) {
  std::lock_guard lock(mutex_);
  auto insert = sqlite::Prepare(db_.get(),
                                "INSERT OR IGNORE INTO acks(sequence, server_id) SELECT ?1, ?2"
                                " WHERE EXISTS(SELECT 1 FROM outbox WHERE sequence = ?1)");
  if (!insert.ok()) return Internal(path_ + ": " + insert.status().message());
  sqlite3_bind_int64(insert->get(), 1, static_cast<sqlite3_int64>(sequence));
  sqlite3_bind_text(insert->get(), 2, server_id.c_str(), -1, SQLITE_TRANSIENT);
  if (sqlite3_step(insert->get()) != SQLITE_DONE) {
    return Internal(path_ + ": recording an acknowledgement: " + sqlite::ErrorMessage(db_.get()));
  }
  Result<std::vector<std::string>> acked = AckedByLocked(sequence);
  if (!acked.ok()) return acked.status();
  for (const std::string& server : required) {
    if (std::find(acked->begin(), acked->end(), server) == acked->end()) return false;
  }
  FLEETLOC_RETURN_IF_ERROR(RemoveLocked(sequence));
  return true;
}

Result<std::vector<std::string>> PatchOutbox::AckedByLocked(uint64_t sequence) {
  auto select = sqlite::Prepare(db_.get(), "SELECT server_id FROM acks WHERE sequence = ?1");
  if (!select.ok()) return Internal(path_ + ": " + select.status().message());
  sqlite3_bind_int64(select->get(), 1, static_cast<sqlite3_int64>(sequence));
  std::vector<std::string> servers;
  while (sqlite3_step(select->get()) == SQLITE_ROW) {
    servers.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(select->get(), 0)));
  }
  return servers;
}

Status PatchOutbox::Remove(uint64_t sequence) {
  std::lock_guard lock(mutex_);
  return RemoveLocked(sequence);
}

Status PatchOutbox::RemoveLocked(uint64_t sequence) {
  // Acks first: interrupted in between, the patch is only sent again (servers are idempotent).
  for (const char* sql :
       {"DELETE FROM acks WHERE sequence = ?1", "DELETE FROM outbox WHERE sequence = ?1"}) {
    auto remove = sqlite::Prepare(db_.get(), sql);
    if (!remove.ok()) return Internal(path_ + ": " + remove.status().message());
    sqlite3_bind_int64(remove->get(), 1, static_cast<sqlite3_int64>(sequence));
    if (sqlite3_step(remove->get()) != SQLITE_DONE) {
      return Internal(path_ + ": " + sqlite::ErrorMessage(db_.get()));
    }
  }
  return Status::Ok();
}

Result<long long> PatchOutbox::Dropped() {
  std::lock_guard lock(mutex_);
  auto count = sqlite::Prepare(db_.get(), "SELECT value FROM meta WHERE name = 'dropped'");
  if (!count.ok() || sqlite3_step(count->get()) != SQLITE_ROW)
    return Internal(path_ + ": reading the drop count");
  return static_cast<long long>(sqlite3_column_int64(count->get(), 0));
}

Result<long long> PatchOutbox::Size() {
  std::lock_guard lock(mutex_);
  auto count = sqlite::Prepare(db_.get(), "SELECT COUNT(*) FROM outbox");
  if (!count.ok() || sqlite3_step(count->get()) != SQLITE_ROW)
    return Internal(path_ + ": counting the outbox");
  return static_cast<long long>(sqlite3_column_int64(count->get(), 0));
}

}  // namespace fleetloc::tracker_agent
