// The test-owned NOTIFY_SOCKET: bind, poll with a time limit, read datagrams.
#include "runtime/notify_listener.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace fleetloc::runtime::testing {

NotifyListener::NotifyListener() {
  char dir_template[] = "/tmp/fleetloc-notify-XXXXXX";
  if (mkdtemp(dir_template) == nullptr) {
    std::perror("mkdtemp");
    std::abort();
  }
  dir_ = dir_template;
  path_ = dir_ + "/notify";
  fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, path_.c_str(), sizeof(address.sun_path) - 1);
  if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    std::perror("notify socket");
    std::abort();
  }
}

NotifyListener::~NotifyListener() {
  if (fd_ >= 0) close(fd_);
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

std::string NotifyListener::Receive(std::chrono::milliseconds limit) {
  pollfd ready{fd_, POLLIN, 0};
  if (poll(&ready, 1, static_cast<int>(limit.count())) <= 0) return "";
  char buffer[4096];
  const ssize_t n = recv(fd_, buffer, sizeof(buffer), 0);
  return n > 0 ? std::string(buffer, static_cast<size_t>(n)) : "";
}

std::vector<std::string> NotifyListener::ReceiveFor(std::chrono::milliseconds window) {
  std::vector<std::string> messages;
  const auto end = std::chrono::steady_clock::now() + window;
  for (auto now = std::chrono::steady_clock::now(); now < end;
       now = std::chrono::steady_clock::now()) {
    std::string message = Receive(std::chrono::duration_cast<std::chrono::milliseconds>(end - now));
    if (!message.empty()) messages.push_back(std::move(message));
  }
  return messages;
}

bool HasLine(const std::string& message, const std::string& line) {
  std::istringstream lines(message);
  for (std::string l; std::getline(lines, l);) {
    if (l == line) return true;
  }
  return false;
}

}  // namespace fleetloc::runtime::testing
