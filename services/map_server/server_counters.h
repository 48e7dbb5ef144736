// Named event counters of a service (requests served, inputs rejected by kind, ...), safe to
// bump from any thread, with the last error kept for the health report.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace fleetloc::map_server {

class ServerCounters {
 public:
  // The counters exist from the start (so health shows zeros) in this order.
  explicit ServerCounters(const std::vector<std::string>& names);

  // Adds `n` to counter `name` (checked: must be one of the names given at construction).
  void Add(const std::string& name, std::uint64_t n = 1);
  // Counts a rejected input under `name` and remembers `message` as the last error.
  void Reject(const std::string& name, const std::string& message);

  std::uint64_t Get(const std::string& name) const;
  std::vector<std::pair<std::string, std::uint64_t>> Snapshot() const;
  // Sum of every counter whose name starts with "rejected_".
  std::uint64_t TotalRejected() const;
  std::string last_error() const;

 private:
  std::vector<std::string> order_;
  std::map<std::string, std::unique_ptr<std::atomic<std::uint64_t>>> counters_;
  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace fleetloc::map_server
