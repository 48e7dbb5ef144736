// Token buckets and quotas for patches.
#include "map_server/patch_budget.h"

#include <algorithm>

namespace fleetloc::map_server {

const char* BudgetVerdictName(BudgetVerdict verdict) {
  switch (verdict) {
    case BudgetVerdict::kAccept:
      return "patches_accepted";
    case BudgetVerdict::kRateLimited:
      return "patches_rate_limited";
    case BudgetVerdict::kOverVehicleQuota:
      return "patches_over_vehicle_quota";
    case BudgetVerdict::kOverTotalQuota:
      return "patches_over_total_quota";
  }
  return "unknown";
}

BudgetVerdict PatchBudget::Admit(const std::string& vehicle, long long bytes, double now_s) {
  std::lock_guard lock(mutex_);
  const PatchUsage stored = usage_[vehicle], pending = pending_[vehicle];
  const PatchUsage used{stored.patches + pending.patches, stored.bytes + pending.bytes};
  if (used.patches + 1 > options_.max_patches_per_vehicle ||
      used.bytes + bytes > options_.max_bytes_per_vehicle) {
    return BudgetVerdict::kOverVehicleQuota;
  }
  if (total_bytes_ + bytes > options_.max_bytes_total) return BudgetVerdict::kOverTotalQuota;
  auto it = buckets_.find(vehicle);
  if (it == buckets_.end()) {
    if (buckets_.size() >= options_.max_vehicles) {
      buckets_.erase(std::min_element(
          buckets_.begin(), buckets_.end(),
          [](const auto& a, const auto& b) { return a.second.last_s < b.second.last_s; }));
    }
    it = buckets_.emplace(vehicle, Bucket{static_cast<double>(options_.burst), now_s}).first;
  }
  Bucket& b = it->second;
  b.tokens =
      std::min<double>(options_.burst, b.tokens + (now_s - b.last_s) * options_.patches_per_s);
  b.last_s = now_s;
  if (b.tokens < 1.0) return BudgetVerdict::kRateLimited;
  b.tokens -= 1.0;
  Add(&pending_[vehicle], 1, bytes);
  total_bytes_ += bytes;
  return BudgetVerdict::kAccept;
}

void PatchBudget::Add(PatchUsage* usage, long long patches, long long bytes) {
  usage->patches = std::max(0LL, usage->patches + patches);
  usage->bytes = std::max(0LL, usage->bytes + bytes);
}

void PatchBudget::Commit(const std::string& vehicle, long long bytes) {
  std::lock_guard lock(mutex_);
  Add(&pending_[vehicle], -1, -bytes);
  Add(&usage_[vehicle], 1, bytes);
}

void PatchBudget::Unreserve(const std::string& vehicle, long long bytes) {
  std::lock_guard lock(mutex_);
  Add(&pending_[vehicle], -1, -bytes);
  total_bytes_ = std::max(0LL, total_bytes_ - bytes);
}

void PatchBudget::SetUsage(std::map<std::string, PatchUsage> usage) {
  std::lock_guard lock(mutex_);
  usage_ = std::move(usage);
  total_bytes_ = 0;
  for (const auto& [vehicle, u] : usage_) total_bytes_ += u.bytes;
  for (const auto& [vehicle, u] : pending_) total_bytes_ += u.bytes;
}

PatchUsage PatchBudget::Usage(const std::string& vehicle) const {
  std::lock_guard lock(mutex_);
  PatchUsage sum;
  if (const auto it = usage_.find(vehicle); it != usage_.end()) sum = it->second;
  if (const auto it = pending_.find(vehicle); it != pending_.end()) {
    Add(&sum, it->second.patches, it->second.bytes);
  }
  return sum;
}

}  // namespace fleetloc::map_server
