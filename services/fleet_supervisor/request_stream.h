// The httplib::Stream a worker thread hands to httplib for one request: first the bytes the
// connection front already read off the socket (the whole head and body), then the socket itself
// (non-blocking; every read and write waits with poll() at most until its deadline). Written
// because httplib 0.11's own socket stream waits per call only (a peer trickling bytes is never cut
// off) and is internal to the library.
#pragma once

#include <httplib.h>

#include <string>

#include "fleet_supervisor/http_socket.h"

namespace fleetloc::fleet_supervisor {

class RequestStream : public httplib::Stream {
 public:
  // Reads past `received` wait until `read_deadline`; the response must be written by
  // `write_deadline`.
  RequestStream(int fd, std::string received, SteadyClock::time_point read_deadline,
                SteadyClock::time_point write_deadline);

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return fd_; }

  // The received bytes httplib did not read (the start of a pipelined next request).
  std::string TakeUnread();

 private:
  bool WaitFor(short events, SteadyClock::time_point deadline) const;

  int fd_;
  std::string received_;
  size_t offset_ = 0;
  SteadyClock::time_point read_deadline_, write_deadline_;
};

}  // namespace fleetloc::fleet_supervisor
