// Exponential backoff per client and overall.
#include "fleet_supervisor/auth_throttle.h"

#include <algorithm>
#include <cmath>

namespace fleetloc::fleet_supervisor {

double AuthThrottle::WaitOf(const Record& r, int free_failures, double now_s) const {
  if (r.failures < free_failures) return 0;
  const int beyond = std::min(r.failures - free_failures, 30);
  const double backoff =
      std::min(options_.base_backoff_s * std::pow(2.0, beyond), options_.max_backoff_s);
  return std::max(0.0, r.last_failure_s + backoff - now_s);
}

double AuthThrottle::RetryAfter(const std::string& client, double now_s) {
  std::lock_guard lock(mutex_);
  const auto it = clients_.find(client);
  const double own = it == clients_.end() ? 0 : WaitOf(it->second, options_.free_failures, now_s);
  return std::max(own, WaitOf(global_, options_.global_free_failures, now_s));
}

void AuthThrottle::Failed(const std::string& client, double now_s) {
  std::lock_guard lock(mutex_);
  // The global count forgets failures after a quiet spell as long as the longest wait.
  if (now_s - global_.last_failure_s > options_.max_backoff_s) global_.failures = 0;
  ++global_.failures;
  global_.last_failure_s = now_s;
  if (!clients_.count(client) && clients_.size() >= options_.max_clients) {
    const auto oldest =
        std::min_element(clients_.begin(), clients_.end(), [](const auto& a, const auto& b) {
          return a.second.last_failure_s < b.second.last_failure_s;
        });
    clients_.erase(oldest);
  }
  Record& r = clients_[client];
  ++r.failures;
  r.last_failure_s = now_s;
}

void AuthThrottle::Succeeded(const std::string& client) {
  std::lock_guard lock(mutex_);
  clients_.erase(client);
}

}  // namespace fleetloc::fleet_supervisor
