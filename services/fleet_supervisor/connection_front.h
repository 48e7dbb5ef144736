// The supervisor's connection front: one thread (epoll) holds every connection that is not being
// answered — new ones, ones sending their request, idle kept-alive ones — and reads each request
// whole (head within header_timeout_s, within the byte, field and body limits, Host and target
// checked: request_checks.h) before handing it on: GET /api/events to the live stream hub, every
// other request to the bounded worker pool. So idle, slow or flooding peers cost an entry in the
// epoll set and at most a bounded buffer, never a worker thread. Over a limit a peer gets the
// matching status (408, 413, 421, 431, 503, ...) and is closed, counted in SupervisorCounters.
//
// Written because cpp-httplib 0.11 (Debian 12) has a thread per connection from accept to close,
// no limit on connections or header fields and no deadline for a whole head: 16 idle sockets
// starved its pool and one endless head grew the process without bound. httplib still parses and
// answers every request (worker threads call its process_request).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "base/status.h"
#include "fleet_supervisor/http_limits.h"
#include "fleet_supervisor/http_socket.h"
#include "fleet_supervisor/request_checks.h"
#include "fleet_supervisor/shared_fleet.h"

namespace fleetloc::fleet_supervisor {

// A request read whole: its socket, its bytes (head, body and whatever followed them) and how
// many requests the connection carried before it.
struct ReadyRequest {
  int fd = -1;
  std::string bytes;
  int served = 0;
};

class ConnectionFront {
 public:
  // `to_workers` takes a ready request (false: no room, the front answers 503); `to_streams` takes
  // the socket of a checked GET /api/events (its request bytes are consumed).
  ConnectionFront(const HttpLimits& limits, RequestPolicy policy,
                  std::function<bool(ReadyRequest&)> to_workers,
                  std::function<void(int)> to_streams, SupervisorCounters* counters);
  ~ConnectionFront();

  Status Start();
  // Closes every connection it holds and joins its thread. Idempotent.
  void Stop();

  // A socket just accepted (any thread): refused with 503 beyond max_connections, or beyond
  // max_connections_per_address from its peer's address.
  void Adopt(int fd);
  // A worker is done with a connection: kept alive (its unread bytes and request count come back)
  // or closed.
  void Done(int fd, std::string unread, int served, bool keep_alive);

 private:
  struct Connection {
    int fd = -1;
    std::string buffer;
    int served = 0;
    bool idle = true;       // nothing of the next request received yet
    size_t head_bytes = 0;  // once the head is complete
    size_t body_bytes = 0;
    bool stream = false;  // the request is GET /api/events
    SteadyClock::time_point deadline;
  };
  struct Handover {
    int fd;
    std::string unread;
    int served;
  };

  void Loop();
  void TakeHandovers();
  void Add(Handover h);
  void OnReadable(Connection& c);
  // Decides on the bytes received so far: wait, refuse, or hand the request on.
  void Advance(Connection& c);
  void Dispatch(Connection& c);
  void Refuse(Connection& c, int status, const std::string& message,
              std::atomic<uint64_t>* counter);
  void Forget(Connection& c, bool close_socket);
  void SetDeadline(Connection& c, SteadyClock::time_point deadline);
  // Counts `fd` against its peer's address; false when that address is at its limit.
  bool HoldAddress(int fd);
  // `fd` is closed or handed to the stream hub: no longer counted against its address.
  void ReleaseAddress(int fd);
  void ExpireDeadlines();

  const HttpLimits limits_;
  const RequestPolicy policy_;
  const HeadLimits head_limits_;
  std::function<bool(ReadyRequest&)> to_workers_;
  std::function<void(int)> to_streams_;
  SupervisorCounters* counters_;
  int epoll_ = -1, wake_ = -1;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::mutex handover_mutex_;
  std::vector<Handover> handovers_;
  std::mutex address_mutex_;  // any thread: accept, workers (Done) and the loop
  std::unordered_map<std::string, int> held_by_address_;
  std::unordered_map<int, std::string> address_of_;
  // Loop thread only:
  std::unordered_map<int, Connection> connections_;
  std::set<std::pair<SteadyClock::time_point, int>> deadlines_;
  size_t buffered_bytes_ = 0;
};

}  // namespace fleetloc::fleet_supervisor
