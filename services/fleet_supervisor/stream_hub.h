// The live stream (Server-Sent Events, /api/events) without a thread per client: one thread
// (epoll) holds every stream socket and writes each new fleet snapshot to all of them without
// blocking. A client that reads slowly skips snapshots (it gets the newest once it has taken the
// previous one); one that takes nothing for write_timeout_s is dropped; an idle stream gets a
// comment line every stream_keep_alive_s. At most max_streams are open; more get 503.
//
// Written because cpp-httplib 0.11 serves a stream from a chunked content provider that holds one
// pool thread for the stream's whole life: 16 dashboard tabs took every thread of the API.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "base/status.h"
#include "fleet_supervisor/event_stream.h"
#include "fleet_supervisor/http_limits.h"
#include "fleet_supervisor/http_socket.h"
#include "fleet_supervisor/shared_fleet.h"

namespace fleetloc::fleet_supervisor {

class StreamHub {
 public:
  StreamHub(EventStream* stream, const HttpLimits& limits, SupervisorCounters* counters);
  ~StreamHub();

  Status Start();
  // Closes every stream and joins the thread. Idempotent.
  void Stop();
  // A socket whose request was a checked GET /api/events (any thread).
  void Adopt(int fd);

 private:
  struct Client {
    int fd = -1;
    std::shared_ptr<const std::string> sending;  // the message being written, or null
    size_t offset = 0;
    uint64_t sent_seq = 0;          // the snapshot last queued to it
    bool writable_armed = false;    // EPOLLOUT requested
    SteadyClock::time_point since;  // when `sending` started, or the last write ended
  };

  void Loop();
  void AddClient(int fd);
  void Feed(Client& c, SteadyClock::time_point now);
  void Flush(Client& c, SteadyClock::time_point now);
  void Arm(Client& c, bool writable);
  void Drop(Client& c, bool stalled);
  void Tick(SteadyClock::time_point now);
  // The newest snapshot as one SSE message (built once per snapshot).
  void RefreshMessage();

  EventStream* stream_;
  const HttpLimits limits_;
  SupervisorCounters* counters_;
  std::shared_ptr<int> wake_;  // eventfd, shared with the EventStream listener
  int epoll_ = -1;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::mutex pending_mutex_;
  std::vector<int> pending_;
  // Loop thread only:
  std::unordered_map<int, Client> clients_;
  uint64_t message_seq_ = 0;
  std::shared_ptr<const std::string> message_;
};

}  // namespace fleetloc::fleet_supervisor
