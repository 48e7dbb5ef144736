// Hostile HTTP clients: idle, streaming, slow and flooding connections.
#include "harness/supervisor/http_abuse.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>

#include "io/loopback_socket.h"

namespace fleetloc::bench {
namespace {

using namespace std::chrono_literals;

int Connect(int port) { return io::ConnectLoopback(port); }

// True when the server closed `fd` (or reset it), without reading what it sent.
bool ClosedByServer(int fd) {
  pollfd p{fd, POLLRDHUP, 0};
  return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

// Keeps `count` connections open (reconnecting what the server closes) until `running` ends;
// `opened(fd)` runs on each new one, `tick(fd)` on each open one every `period`.
template <typename Opened, typename Tick>
void HoldConnections(int port, int count, std::chrono::milliseconds period,
                     const std::atomic<bool>& running, std::atomic<long long>* connects,
                     std::atomic<long long>* closed, Opened opened, Tick tick) {
  std::vector<int> fds(static_cast<size_t>(count), -1);
  while (running) {
    for (int& fd : fds) {
      if (!running) break;
      if (fd >= 0 && ClosedByServer(fd)) {
        ::close(fd);
        fd = -1;
        ++*closed;
      }
      if (fd < 0 && (fd = Connect(port)) >= 0) {
        ++*connects;
        opened(fd);
      }
      if (fd >= 0) tick(fd);
    }
    std::this_thread::sleep_for(period);
  }
  for (int fd : fds) {
    if (fd >= 0) ::close(fd);
  }
}

void SendSome(int fd, const std::string& bytes) {
  (void)::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

}  // namespace

HttpAbuse::HttpAbuse(AbuseOptions options) : options_(options) {}

HttpAbuse::~HttpAbuse() { Stop(); }

void HttpAbuse::Start() {
  running_ = true;
  threads_.emplace_back([this] { Idle(); });
  threads_.emplace_back([this] { Streams(); });
  threads_.emplace_back([this] { Slow(); });
  threads_.emplace_back([this] { Flood(); });
}

void HttpAbuse::Stop() {
  running_ = false;
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

AbuseStats HttpAbuse::stats() const {
  return {connects_, closed_, streams_answered_, streams_refused_, flood_bytes_ / 1048576.0};
}

void HttpAbuse::Idle() {
  HoldConnections(
      options_.port, options_.idle, 200ms, running_, &connects_, &closed_, [](int) {}, [](int) {});
}

void HttpAbuse::Streams() {
  HoldConnections(
      options_.port, options_.streams, 50ms, running_, &connects_, &closed_,
      [&](int fd) {
        SendSome(fd, "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
        char status[13] = {};
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, 2000) > 0 && ::recv(fd, status, 12, MSG_PEEK) == 12) {
          ++(std::strncmp(status, "HTTP/1.1 200", 12) == 0 ? streams_answered_ : streams_refused_);
        }
      },
      [&](int fd) {
        // Every second stream (by descriptor) reads what it gets; the others never read.
        if (fd % 2 == 0) {
          char sink[65536];
          while (::recv(fd, sink, sizeof sink, MSG_DONTWAIT) > 0) {
          }
        }
      });
}

void HttpAbuse::Slow() {
  HoldConnections(
      options_.port, options_.slow, std::chrono::milliseconds(options_.slow_period_ms), running_,
      &connects_, &closed_,
      [](int fd) { SendSome(fd, "GET /api/fleet HTTP/1.1\r\nHost: 127.0.0.1\r\n"); },
      [](int fd) { SendSome(fd, "X"); });
}

void HttpAbuse::Flood() {
  const std::string line = "X-Flood: " + std::string(1000, 'f') + "\r\n";
  std::string block = "GET /api/fleet HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  while (block.size() < 65536) block += line;
  const long long target = static_cast<long long>(options_.flood_mb * 1048576.0);
  while (running_ && flood_bytes_ < target) {
    const int fd = Connect(options_.port);
    if (fd < 0) {
      std::this_thread::sleep_for(10ms);
      continue;
    }
    ++connects_;
    timeval timeout{0, 200000};
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    for (;;) {
      const ssize_t n = ::send(fd, block.data(), block.size(), MSG_NOSIGNAL);
      if (n <= 0 || !running_) break;  // closed by the server (or not taking more)
      flood_bytes_ += n;
      if (flood_bytes_ >= target) break;
    }
    ++closed_;
    ::close(fd);
  }
}

}  // namespace fleetloc::bench
