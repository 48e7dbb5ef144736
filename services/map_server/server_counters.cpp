// Named atomic counters with the last error message.
#include "map_server/server_counters.h"

#include <spdlog/spdlog.h>

#include "base/status.h"

namespace fleetloc::map_server {

ServerCounters::ServerCounters(const std::vector<std::string>& names) : order_(names) {
  for (const std::string& name : names) {
    counters_.emplace(name, std::make_unique<std::atomic<std::uint64_t>>(0));
  }
}

void ServerCounters::Add(const std::string& name, std::uint64_t n) {
  const auto it = counters_.find(name);
  FLEETLOC_CHECK(it != counters_.end());
  it->second->fetch_add(n, std::memory_order_relaxed);
}

void ServerCounters::Reject(const std::string& name, const std::string& message) {
  Add(name);
  spdlog::warn("{}: {}", name, message);
  std::lock_guard lock(error_mutex_);
  last_error_ = message;
}

std::uint64_t ServerCounters::Get(const std::string& name) const {
  const auto it = counters_.find(name);
  FLEETLOC_CHECK(it != counters_.end());
  return it->second->load(std::memory_order_relaxed);
}

std::vector<std::pair<std::string, std::uint64_t>> ServerCounters::Snapshot() const {
  std::vector<std::pair<std::string, std::uint64_t>> out;
  for (const std::string& name : order_) out.emplace_back(name, Get(name));
  return out;
}

std::uint64_t ServerCounters::TotalRejected() const {
  std::uint64_t total = 0;
  for (const std::string& name : order_) {
    if (name.rfind("rejected_", 0) == 0) total += Get(name);
  }
  return total;
}

std::string ServerCounters::last_error() const {
  std::lock_guard lock(error_mutex_);
  return last_error_;
}

}  // namespace fleetloc::map_server
