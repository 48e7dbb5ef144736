// The agent's patch outbox: floor patches waiting for the map server's acknowledgement, kept in
// an SQLite file so they survive an agent restart (and a map server outage). Sequence numbers
// are persisted too, so a restarted agent never reuses one (the server is idempotent on them).
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mosaic/sqlite_util.h"
#include "transport/patch_client.h"

namespace fleetloc::tracker_agent {

class PatchOutbox {
 public:
  // Opens (creating if needed) the outbox file. Internal naming the file on SQLite errors.
  static Result<std::unique_ptr<PatchOutbox>> Open(const std::string& path);

  // Stores `patch` under the next sequence number (written into it) in one transaction.
  Result<uint64_t> Add(transport::PatchToSend* patch);
  // Up to `max` patches never sent or sent more than `retry_after_s` before `now_s`, oldest first.
  Result<std::vector<transport::PatchToSend>> Due(double now_s, double retry_after_s, int max);
  Status MarkSent(uint64_t sequence, double now_s);
  // Forgets an acknowledged patch (stored, duplicate or rejected by the server).
  Status Remove(uint64_t sequence);
  Result<long long> Size();

 private:
  PatchOutbox(std::string path, mosaic::sqlite::Db db) : path_(std::move(path)), db_(std::move(db)) {}
  Status Exec(const std::string& what, const char* sql);
  const std::string path_;
  std::mutex mutex_;
  mosaic::sqlite::Db db_;
};

}  // namespace fleetloc::tracker_agent
