// Hostile HTTP clients against one port, for the supervisor's robustness test and
// `fleetctl bench supervisor-abuse`: idle sockets that never send a byte, live streams (half of
// them never read), slow senders trickling a head that never ends, and a flood of header lines.
// Each kind keeps its count of connections open for the whole run, reconnecting what the server
// closes. Numbers for tests and benchmarks; no assertions here.
#pragma once

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

namespace fleetloc::bench {

struct AbuseOptions {
  int port = 0;       // on 127.0.0.1
  int idle = 2000;    // sockets that connect and send nothing
  int streams = 100;  // GET /api/events; every second one never reads
  int slow = 50;      // sockets sending one byte of an endless head every slow_period_ms
  int slow_period_ms = 100;
  double flood_mb = 400;  // header bytes to send in total (header lines, no blank line)
};

struct AbuseStats {
  long long connects = 0;          // every connection opened (all kinds, with reconnects)
  long long closed_by_server = 0;  // connections the server closed
  long long streams_answered = 0;  // stream requests answered 200
  long long streams_refused = 0;   // answered otherwise (503: too many)
  double flood_mb_sent = 0;
};

class HttpAbuse {
 public:
  explicit HttpAbuse(AbuseOptions options);
  ~HttpAbuse();  // Stop()

  void Start();
  // Stops every client and closes its sockets. Idempotent.
  void Stop();
  AbuseStats stats() const;

 private:
  void Idle();
  void Streams();
  void Slow();
  void Flood();

  const AbuseOptions options_;
  std::atomic<bool> running_{false};
  std::vector<std::thread> threads_;
  std::atomic<long long> connects_{0}, closed_{0}, streams_answered_{0}, streams_refused_{0};
  std::atomic<long long> flood_bytes_{0};
};

}  // namespace fleetloc::bench
