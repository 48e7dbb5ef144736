// Backoff on wrong maintainer tokens: each client (by address) may get the token wrong a few
// times; after that, every further attempt must wait twice as long as the last (up to a cap)
// before it is even checked, so guessing a token online takes forever. A global budget does the
// same across all clients (many addresses guessing together). A right token clears its client.
// Thread-safe; the clock is passed in (seconds, any monotonic origin).
#pragma once

#include <cstddef>
#include <map>
#include <mutex>
#include <string>

namespace fleetloc::fleet_supervisor {

struct ThrottleOptions {
  int free_failures = 5;          // per client, before any wait
  int global_free_failures = 50;  // all clients together (forgotten after max_backoff_s quiet)
  double base_backoff_s = 1.0;    // the first wait; doubled with each further failure
  double max_backoff_s = 60.0;
  size_t max_clients = 4096;  // clients remembered (the oldest are forgotten)
};

class AuthThrottle {
 public:
  explicit AuthThrottle(ThrottleOptions options = {}) : options_(options) {}

  // Seconds `client` must still wait before an attempt is checked (0: now).
  double RetryAfter(const std::string& client, double now_s);
  void Failed(const std::string& client, double now_s);
  void Succeeded(const std::string& client);

 private:
  struct Record {
    int failures = 0;
    double last_failure_s = 0;
  };
  double WaitOf(const Record& r, int free_failures, double now_s) const;

  const ThrottleOptions options_;
  std::mutex mutex_;
  std::map<std::string, Record> clients_;
  Record global_;
};

}  // namespace fleetloc::fleet_supervisor
