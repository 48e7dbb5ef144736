// What the supervisor's HTTP side allows a client (its configuration's "http" object): how many
// connections and live streams, how fast a request's head must arrive and how large it may be,
// how many requests are answered at once and how many may wait, which Host names it answers to.
// A slow or hostile client is cut off at these limits and costs itself, not the operators.
#pragma once

#include <string>
#include <vector>

namespace fleetloc::fleet_supervisor {

struct HttpLimits {
  int max_connections = 4096;  // open sockets beside the live streams; beyond: 503 and closed
  // Of those, from one client address; beyond: 503 and closed. 0: no such cap (the default,
  // because on loopback and behind a reverse proxy every client has the same address; set it
  // where clients reach the port directly).
  int max_connections_per_address = 0;
  int max_streams = 256;          // live streams (/api/events); beyond: 503
  int workers = 8;                // threads answering requests (never held by idle or slow peers)
  int queue = 256;                // complete requests waiting for a worker; beyond: 503
  double header_timeout_s = 5.0;  // a request's head and body must arrive within this
  double keep_alive_timeout_s = 5.0;  // an idle kept-alive connection is closed after this
  double write_timeout_s = 10.0;      // a response must be taken by the client within this
  int max_requests_per_connection = 1000;
  int max_header_bytes = 16384;      // request line and header fields; beyond: 431
  int max_header_count = 64;         // header fields; beyond: 431
  int max_body_bytes = 65536;        // beyond: 413
  int max_ranges = 1;                // byte ranges in a Range field; beyond: 416
  int max_buffered_mb = 64;          // request bytes held by all connections together
  double stream_keep_alive_s = 2.0;  // a comment line on an idle live stream this often
  // Host names (or addresses) requests may name; empty: localhost, 127.0.0.1, ::1 and http_bind.
  // "*" allows any (only behind a proxy that checks Host itself).
  std::vector<std::string> allowed_hosts;
  int auth_free_failures = 5;        // wrong tokens per client before it must wait
  double auth_max_backoff_s = 60.0;  // the longest wait (doubling from 1 s)
};

// "" or "<field> <what>" for the first limit out of range.
std::string LimitsProblem(const HttpLimits& limits);

}  // namespace fleetloc::fleet_supervisor
