// cpp-httplib's Server with the supervisor's limits in front of it (http_limits.h): httplib's own
// accept loop hands each new socket straight to the connection front (an inline task queue and an
// override of process_and_close_socket) instead of a pool thread; the front reads each request
// whole and passes it to a bounded pool of workers, which let httplib route and answer it
// (process_request over a RequestStream), then give the connection back to the front while it is
// kept alive. Live streams go to the stream hub. Routes are registered on it as on any
// httplib::Server.
//
// httplib's own per-connection knobs (set_keep_alive_max_count, set_keep_alive_timeout,
// set_read_timeout, the thread pool of new_task_queue) belong to the connection handling this
// replaces; their equivalents are http.max_requests_per_connection, keep_alive_timeout_s,
// header_timeout_s and workers. set_payload_max_length, routing, static files and range
// responses are still httplib's (the front checks sizes and ranges first).
#pragma once

// Eigen (through shared_fleet.h) before httplib: <resolv.h>, which httplib includes, defines
// `_res`, a name Eigen's headers use.
// clang-format off
#include "fleet_supervisor/connection_front.h"
#include <httplib.h>
// clang-format on

#include <memory>
#include <string>

#include "base/status.h"
#include "fleet_supervisor/event_stream.h"
#include "fleet_supervisor/http_limits.h"
#include "fleet_supervisor/shared_fleet.h"
#include "fleet_supervisor/stream_hub.h"
#include "fleet_supervisor/worker_pool.h"

namespace fleetloc::fleet_supervisor {

class GuardedServer : public httplib::Server {
 public:
  GuardedServer(const HttpLimits& limits, RequestPolicy policy, EventStream* stream,
                SupervisorCounters* counters);
  ~GuardedServer() override;

  // Binds `host`:`port` (0: any free port) with a listen backlog deep enough for a burst of
  // connections (httplib's is 5), never sharing the port with another listener (no SO_REUSEPORT);
  // the bound port, or -1 with *error (when given) set to the errno of the failure.
  int Bind(const std::string& host, int port, int* error = nullptr);
  // Starts the front, the stream hub and the workers (before listen_after_bind).
  Status StartGuards();
  // Closes every connection and joins the guards' threads: after stop() and once
  // listen_after_bind() has returned (so no socket is being accepted). Idempotent.
  void StopGuards();

 private:
  // Called by httplib's accept loop for each new socket: the front takes it.
  bool process_and_close_socket(socket_t sock) override;
  // A worker: one request through httplib, then the connection back to the front or closed.
  void Serve(ReadyRequest& request);

  const HttpLimits limits_;
  SupervisorCounters* counters_;
  std::unique_ptr<StreamHub> hub_;
  std::unique_ptr<ConnectionFront> front_;
  std::unique_ptr<WorkerPool<ReadyRequest>> workers_;
};

}  // namespace fleetloc::fleet_supervisor
