// Test helper: a NOTIFY_SOCKET that a test owns (a unix datagram socket in a temporary
// directory), to receive a daemon's sd_notify messages as systemd would.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace fleetloc::runtime::testing {

class NotifyListener {
 public:
  NotifyListener();  // binds a fresh socket; aborts the test process if it cannot
  ~NotifyListener();
  NotifyListener(const NotifyListener&) = delete;
  NotifyListener& operator=(const NotifyListener&) = delete;

  // The value for NOTIFY_SOCKET.
  const std::string& path() const { return path_; }
  // The next message (its lines joined by '\n'), or "" when none came within `limit`.
  std::string Receive(std::chrono::milliseconds limit);
  // Every message received within `window` (waits the whole window).
  std::vector<std::string> ReceiveFor(std::chrono::milliseconds window);

 private:
  int fd_ = -1;
  std::string dir_;
  std::string path_;
};

// True when one of the message's lines is exactly `line` (e.g. "READY=1").
bool HasLine(const std::string& message, const std::string& line);

}  // namespace fleetloc::runtime::testing
