// Thin RAII over the SQLite C API: owned connections and statements, statement reset guards and
// error messages as Status. Used by the tile store, the agent's patch outbox and the supervisor's
// history (fleetloc_sqlite: an adapter library, beside the pure ones).
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "base/status.h"

struct sqlite3;
struct sqlite3_stmt;

namespace fleetloc::sqlite {

struct DbCloser {
  void operator()(sqlite3* db) const;  // sqlite3_close_v2: also rolls back an open transaction
};
struct StmtFinalizer {
  void operator()(sqlite3_stmt* stmt) const;
};
using Db = std::unique_ptr<sqlite3, DbCloser>;
using Stmt = std::unique_ptr<sqlite3_stmt, StmtFinalizer>;

// Opens a connection (flags as for sqlite3_open_v2). On failure the message names the path.
Result<Db> OpenDb(const std::string& path, int flags);

// Compiles one statement; the error carries SQLite's message.
Result<Stmt> Prepare(sqlite3* db, std::string_view sql);

// Runs SQL without results (several statements allowed).
Status Exec(sqlite3* db, const char* sql);

// Removes a database file and its side files (-wal, -shm, -journal), ignoring absent ones. The
// database must not be open.
void RemoveDatabaseFiles(const std::string& path);

// SQLite's current error message of a connection.
std::string ErrorMessage(sqlite3* db);

// Resets and clears a statement's bindings when it goes out of scope, so a reused prepared
// statement never keeps a read transaction open or stale bindings.
class ScopedReset {
 public:
  explicit ScopedReset(sqlite3_stmt* stmt) : stmt_(stmt) {}
  ~ScopedReset();
  ScopedReset(const ScopedReset&) = delete;
  ScopedReset& operator=(const ScopedReset&) = delete;

 private:
  sqlite3_stmt* stmt_;
};

}  // namespace fleetloc::sqlite
