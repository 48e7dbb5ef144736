// The agent's patch outbox: floor patches waiting for the map servers' acknowledgements, kept in
// an SQLite file so they survive an agent restart (and a map server outage). Sequence numbers
// are persisted too, so a restarted agent never reuses one (the server is idempotent on them).
// With the mosaic split across map servers every server keeps a replica of every patch, so a
// patch leaves the outbox only once each of them has acknowledged it; the acknowledgements so far
// are persisted with it.
//
// When a patch was last sent is kept as the monotonic clock's reading together with the boot it
// belongs to (OutboxTime): a monotonic clock restarts at every boot, so a patch sent in an earlier
// boot is due at once after a reboot (the wall clock is not used: it can jump either way).
// The outbox is capped (OutboxLimits): adding beyond the cap drops, from the oldest tenth of the
// patches, the one of lowest quality first; drops are counted in the file.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "sqlite/sqlite_util.h"
#include "transport/patch_client.h"

namespace fleetloc::tracker_agent {

// A moment on this machine: the boot (Linux's boot id) and seconds of its monotonic clock.
struct OutboxTime {
  std::string boot_id;
  double monotonic_s = 0;
};
// Now (the boot id from /proc/sys/kernel/random/boot_id; "" where there is none).
OutboxTime OutboxNow();

struct OutboxLimits {
  long long max_patches = 500;
  long long max_bytes = 256LL << 20;
};

class PatchOutbox {
 public:
  // Opens (creating if needed) the outbox file. Internal naming the file on SQLite errors.
  static Result<std::unique_ptr<PatchOutbox>> Open(const std::string& path,
                                                   OutboxLimits limits = {});

  // Stores `patch` under the next sequence number (written into it) in one transaction, then drops
  // patches while the outbox is over its limits (oldest tenth, lowest quality first; counted).
  // Returns the sequence number.
  Result<uint64_t> Add(transport::PatchToSend* patch);
  // Up to `max` patches never sent, sent in another boot, or sent more than `retry_after_s` before
  // `now`, oldest first.
  Result<std::vector<transport::PatchToSend>> Due(const OutboxTime& now, double retry_after_s,
                                                  int max);
  Status MarkSent(uint64_t sequence, const OutboxTime& now);
  // Records that map server `server_id` stored (or already had) patch `sequence`, and forgets the
  // patch once `server_id` and every server in `required` have. True when it was forgotten.
  Result<bool> Acknowledge(uint64_t sequence, const std::string& server_id,
                           const std::vector<std::string>& required);
  // Forgets a patch for good (rejected by a server: resending cannot help).
  Status Remove(uint64_t sequence);
  Result<long long> Size();
  // Patches dropped because the outbox was full, since the file was made.
  Result<long long> Dropped();

 private:
  PatchOutbox(std::string path, sqlite::Db db, OutboxLimits limits)
      : path_(std::move(path)), db_(std::move(db)), limits_(limits) {}
  // Drops patches until the outbox is within its limits; the number dropped.
  Result<long long> EnforceLimitsLocked();
  Status Exec(const std::string& what, const char* sql);
  Status RemoveLocked(uint64_t sequence);
  Result<std::vector<std::string>> AckedByLocked(uint64_t sequence);
  const std::string path_;
  std::mutex mutex_;
  sqlite::Db db_;
  const OutboxLimits limits_;
};

}  // namespace fleetloc::tracker_agent
