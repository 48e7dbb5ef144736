// The agent's patch outbox: floor patches waiting for the map servers' acknowledgements, kept in
// an SQLite file so they survive an agent restart (and a map server outage). Sequence numbers
// are persisted too, so a restarted agent never reuses one (the server is idempotent on them).
// With the mosaic split across map servers every server keeps a replica of every patch, so a
// patch leaves the outbox only once each of them has acknowledged it; the acknowledgements so far
// are persisted with it.
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
  // Records that map server `server_id` stored (or already had) patch `sequence`, and forgets the
  // patch once `server_id` and every server in `required` have. True when it was forgotten.
  Result<bool> Acknowledge(uint64_t sequence, const std::string& server_id,
                           const std::vector<std::string>& required);
  // Forgets a patch for good (rejected by a server: resending cannot help).
  Status Remove(uint64_t sequence);
  Result<long long> Size();

 private:
  PatchOutbox(std::string path, mosaic::sqlite::Db db) : path_(std::move(path)), db_(std::move(db)) {}
  Status Exec(const std::string& what, const char* sql);
  Status RemoveLocked(uint64_t sequence);
  Result<std::vector<std::string>> AckedByLocked(uint64_t sequence);
  const std::string path_;
  std::mutex mutex_;
  mosaic::sqlite::Db db_;
};

}  // namespace fleetloc::tracker_agent
