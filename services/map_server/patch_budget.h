// What one vehicle (and all together) may put into the map server's patch store: a rate (token
// bucket: patches per second with a burst) and a quota (stored patches and bytes per vehicle, bytes
// for all). A patch over its budget is not acknowledged — the vehicle keeps it and sends it again
// later — so a flooding vehicle costs the server a counter, not its disk. Pure bookkeeping (the
// clock is passed in); thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace fleetloc::map_server {

struct PatchBudgetOptions {
  double patches_per_s = 2.0;  // per vehicle, sustained
  int burst = 20;              // per vehicle, at once
  long long max_patches_per_vehicle = 1000;
  long long max_bytes_per_vehicle = 512LL << 20;
  long long max_bytes_total = 8192LL << 20;
  size_t max_vehicles = 4096;  // rate buckets kept (the least recently used are dropped)
};

enum class BudgetVerdict { kAccept, kRateLimited, kOverVehicleQuota, kOverTotalQuota };
const char* BudgetVerdictName(BudgetVerdict verdict);  // the counter: "patches_rate_limited", ...

struct PatchUsage {
  long long patches = 0;
  long long bytes = 0;
};

class PatchBudget {
 public:
  explicit PatchBudget(PatchBudgetOptions options) : options_(options) {}

  // Decides on a patch of `bytes` from `vehicle` at `now_s`. kAccept takes a token and reserves
  // the patch: Commit once it is stored, Unreserve if it is not stored after all.
  BudgetVerdict Admit(const std::string& vehicle, long long bytes, double now_s);
  void Commit(const std::string& vehicle, long long bytes);
  void Unreserve(const std::string& vehicle, long long bytes);
  // Replaces the stored usage with what the store holds (at start, after re-maps and prunes).
  // Reservations still in flight are kept: the store does not hold them yet (before, a prune
  // while a flood was queued forgot them, and the vehicle got past its quota by a patch).
  void SetUsage(std::map<std::string, PatchUsage> usage);
  // Stored and reserved.
  PatchUsage Usage(const std::string& vehicle) const;

 private:
  struct Bucket {
    double tokens = 0;
    double last_s = 0;
  };
  static void Add(PatchUsage* usage, long long patches, long long bytes);  // clamped at 0

  const PatchBudgetOptions options_;
  mutable std::mutex mutex_;
  std::map<std::string, Bucket> buckets_;
  std::map<std::string, PatchUsage> usage_;    // stored
  std::map<std::string, PatchUsage> pending_;  // admitted, neither stored nor refused yet
  long long total_bytes_ = 0;                  // stored and pending, every vehicle
};

}  // namespace fleetloc::map_server
