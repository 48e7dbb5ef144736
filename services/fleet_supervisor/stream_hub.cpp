// StreamHub: non-blocking fan-out of fleet snapshots to the live stream clients.
#include "fleet_supervisor/stream_hub.h"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

namespace fleetloc::fleet_supervisor {
namespace {

constexpr int kMaxEvents = 256;
constexpr int kTickMs = 250;

constexpr const char* kStreamHead =
    "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-cache\r\n"
    "X-Accel-Buffering: no\r\nConnection: close\r\n\r\n";

const std::shared_ptr<const std::string>& KeepAlive() {
  static const auto message = std::make_shared<const std::string>(": keep-alive\n\n");
  return message;
}

std::chrono::milliseconds Seconds(double s) {
  return std::chrono::milliseconds(static_cast<long long>(s * 1000));
}

void Notify(int fd) {
  const uint64_t one = 1;
  (void)!::write(fd, &one, sizeof one);
}

}  // namespace

StreamHub::StreamHub(EventStream* stream, const HttpLimits& limits, SupervisorCounters* counters)
    : stream_(stream), limits_(limits), counters_(counters) {}

StreamHub::~StreamHub() { Stop(); }

Status StreamHub::Start() {
  const int wake = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
  if (wake < 0 || epoll_ < 0) return Internal("live stream hub: cannot create its epoll set");
  // The listener may still be called after the hub is gone: it holds the eventfd itself.
  wake_ = std::shared_ptr<int>(new int(wake), [](int* fd) {
    ::close(*fd);
    delete fd;
  });
  epoll_event e{};
  e.events = EPOLLIN;
  e.data.fd = wake;
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, wake, &e) != 0)
    return Internal("live stream hub: epoll_ctl failed");
  stream_->SetListener([wake = wake_] { Notify(*wake); });
  running_ = true;
  thread_ = std::thread([this] { Loop(); });
  return Status::Ok();
}

void StreamHub::Stop() {
  if (stream_ != nullptr) stream_->SetListener(nullptr);
  if (running_.exchange(false) && thread_.joinable()) {
    Notify(*wake_);
    thread_.join();
  }
  for (auto& [fd, c] : clients_) {
    CloseSocket(fd);
    --counters_->http_streams_open;
  }
  clients_.clear();
  std::lock_guard lock(pending_mutex_);
  for (int fd : pending_) {
    CloseSocket(fd);
    --counters_->http_streams_open;
  }
  pending_.clear();
  if (epoll_ >= 0) {
    ::close(epoll_);
    epoll_ = -1;
  }
}

void StreamHub::Adopt(int fd) {
  if (!running_) return CloseSocket(fd);
  if (counters_->http_streams_open >= limits_.max_streams) {
    ++counters_->http_streams_refused;
    return AnswerAndClose(fd, 503, "too many live streams open");
  }
  ++counters_->http_streams_open;
  {
    std::lock_guard lock(pending_mutex_);
    pending_.push_back(fd);
  }
  Notify(*wake_);
}

void StreamHub::Loop() {
  epoll_event events[kMaxEvents];
  while (running_) {
    const int n = ::epoll_wait(epoll_, events, kMaxEvents, kTickMs);
    const auto now = SteadyClock::now();
    for (int i = 0; i < n && running_; ++i) {
      const int fd = events[i].data.fd;
      if (fd == *wake_) {
        uint64_t count = 0;
        (void)!::read(fd, &count, sizeof count);
        std::vector<int> added;
        {
          std::lock_guard lock(pending_mutex_);
          added.swap(pending_);
        }
        for (int a : added) AddClient(a);
        RefreshMessage();
        for (auto it = clients_.begin(); it != clients_.end();) Feed((it++)->second, now);
        continue;
      }
      const auto it = clients_.find(fd);
      if (it == clients_.end()) continue;
      if (events[i].events & (EPOLLIN | EPOLLRDHUP | EPOLLHUP | EPOLLERR)) {
        // A stream client sends nothing; data is discarded, end of stream or an error ends it.
        char sink[1024];
        const ssize_t r = ::recv(fd, sink, sizeof sink, MSG_DONTWAIT);
        if (r == 0 || (r < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
          Drop(it->second, false);
          continue;
        }
      }
      if (events[i].events & EPOLLOUT) Flush(it->second, now);
    }
    Tick(SteadyClock::now());
  }
}

void StreamHub::AddClient(int fd) {
  const auto now = SteadyClock::now();
  if (!SendBefore(fd, kStreamHead, now)) {
    CloseSocket(fd);
    --counters_->http_streams_open;
    return;
  }
  epoll_event e{};
  e.events = EPOLLIN | EPOLLRDHUP;
  e.data.fd = fd;
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, fd, &e) != 0) {
    CloseSocket(fd);
    --counters_->http_streams_open;
    return;
  }
  Client& c = clients_[fd];
  c.fd = fd;
  c.since = now;
  RefreshMessage();
  Feed(c, now);
}

void StreamHub::RefreshMessage() {
  const auto [seq, data] = stream_->Latest();
  if (seq == message_seq_ || data == nullptr) return;
  message_ = std::make_shared<const std::string>("data: " + *data + "\n\n");
  message_seq_ = seq;
}

void StreamHub::Feed(Client& c, SteadyClock::time_point now) {
  if (c.sending != nullptr || message_ == nullptr || c.sent_seq >= message_seq_) return;
  c.sending = message_;
  c.offset = 0;
  c.sent_seq = message_seq_;
  c.since = now;
  Flush(c, now);
}

void StreamHub::Flush(Client& c, SteadyClock::time_point now) {
  while (c.sending != nullptr) {
    const std::string& m = *c.sending;
    const ssize_t n =
        ::send(c.fd, m.data() + c.offset, m.size() - c.offset, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return Arm(c, true);
    if (n <= 0) return Drop(c, false);
    c.offset += static_cast<size_t>(n);
    if (c.offset < m.size()) continue;
    c.sending = nullptr;
    c.since = now;
    // A newer snapshot came while this one was being taken: it goes next (those between, never).
    if (message_ != nullptr && c.sent_seq < message_seq_) {
      c.sending = message_;
      c.offset = 0;
      c.sent_seq = message_seq_;
    }
  }
  Arm(c, false);
}

void StreamHub::Arm(Client& c, bool writable) {
  if (c.writable_armed == writable) return;
  epoll_event e{};
  e.events = EPOLLIN | EPOLLRDHUP | (writable ? EPOLLOUT : 0u);
  e.data.fd = c.fd;
  if (::epoll_ctl(epoll_, EPOLL_CTL_MOD, c.fd, &e) == 0) c.writable_armed = writable;
}

void StreamHub::Drop(Client& c, bool stalled) {
  if (stalled) ++counters_->http_streams_dropped;
  const int fd = c.fd;
  ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
  CloseSocket(fd);
  --counters_->http_streams_open;
  clients_.erase(fd);
}

void StreamHub::Tick(SteadyClock::time_point now) {
  for (auto it = clients_.begin(); it != clients_.end();) {
    Client& c = (it++)->second;
    if (c.sending != nullptr) {
      if (now - c.since > Seconds(limits_.write_timeout_s)) Drop(c, true);
    } else if (now - c.since >= Seconds(limits_.stream_keep_alive_s)) {
      c.sending = KeepAlive();
      c.offset = 0;
      c.since = now;
      Flush(c, now);
    }
  }
}

}  // namespace fleetloc::fleet_supervisor
