// RequestStream: pre-read bytes, then the socket, under deadlines.
#include "fleet_supervisor/request_stream.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace fleetloc::fleet_supervisor {

RequestStream::RequestStream(int fd, std::string received, SteadyClock::time_point read_deadline,
                             SteadyClock::time_point write_deadline)
    : fd_(fd),
      received_(std::move(received)),
      read_deadline_(read_deadline),
      write_deadline_(write_deadline) {}

bool RequestStream::WaitFor(short events, SteadyClock::time_point deadline) const {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
  if (left.count() <= 0) return false;
  pollfd p{fd_, events, 0};
  return ::poll(&p, 1, static_cast<int>(left.count())) > 0 && (p.revents & events) != 0;
}

bool RequestStream::is_readable() const {
  return offset_ < received_.size() || WaitFor(POLLIN, read_deadline_);
}

bool RequestStream::is_writable() const { return WaitFor(POLLOUT, write_deadline_); }

ssize_t RequestStream::read(char* ptr, size_t size) {
  if (offset_ < received_.size()) {
    const size_t n = std::min(size, received_.size() - offset_);
    std::memcpy(ptr, received_.data() + offset_, n);
    offset_ += n;
    return static_cast<ssize_t>(n);
  }
  for (;;) {
    const ssize_t n = ::recv(fd_, ptr, size, 0);
    if (n >= 0) return n;
    if (errno == EINTR) continue;
    if ((errno != EAGAIN && errno != EWOULDBLOCK) || !WaitFor(POLLIN, read_deadline_)) return -1;
  }
}

ssize_t RequestStream::write(const char* ptr, size_t size) {
  return SendBefore(fd_, {ptr, size}, write_deadline_) ? static_cast<ssize_t>(size) : -1;
}

void RequestStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (::getpeername(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) AddressOf(a, ip, port);
}

void RequestStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) AddressOf(a, ip, port);
}

std::string RequestStream::TakeUnread() {
  std::string unread = received_.substr(offset_);
  received_.clear();
  offset_ = 0;
  return unread;
}

}  // namespace fleetloc::fleet_supervisor
