// ConnectionFront: the epoll loop that reads requests whole before a worker sees them.
#include "fleet_supervisor/connection_front.h"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace fleetloc::fleet_supervisor {
namespace {

constexpr int kMaxEvents = 512;
constexpr size_t kReadChunk = 16384;

std::chrono::milliseconds Seconds(double s) {
  return std::chrono::milliseconds(static_cast<long long>(s * 1000));
}

}  // namespace

ConnectionFront::ConnectionFront(const HttpLimits& limits, RequestPolicy policy,
                                 std::function<bool(ReadyRequest&)> to_workers,
                                 std::function<void(int)> to_streams, SupervisorCounters* counters)
    : limits_(limits),
      policy_(std::move(policy)),
      head_limits_{static_cast<size_t>(limits.max_header_bytes), limits.max_header_count},
      to_workers_(std::move(to_workers)),
      to_streams_(std::move(to_streams)),
      counters_(counters) {}

ConnectionFront::~ConnectionFront() { Stop(); }

Status ConnectionFront::Start() {
  epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
  wake_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (epoll_ < 0 || wake_ < 0) return Internal("HTTP front: cannot create its epoll set");
  epoll_event e{};
  e.events = EPOLLIN;
  e.data.fd = wake_;
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, wake_, &e) != 0)
    return Internal("HTTP front: epoll_ctl failed");
  running_ = true;
  thread_ = std::thread([this] { Loop(); });
  return Status::Ok();
}

void ConnectionFront::Stop() {
  if (running_.exchange(false) && thread_.joinable()) {
    const uint64_t one = 1;
    (void)!::write(wake_, &one, sizeof one);
    thread_.join();
  }
  for (auto& [fd, c] : connections_) {
    CloseSocket(fd);
    --counters_->http_connections_open;
  }
  connections_.clear();
  deadlines_.clear();
  std::lock_guard lock(handover_mutex_);
  for (const Handover& h : handovers_) {
    CloseSocket(h.fd);
    --counters_->http_connections_open;
  }
  handovers_.clear();
  if (epoll_ >= 0) {
    ::close(epoll_);
    epoll_ = -1;
  }
  if (wake_ >= 0) {
    ::close(wake_);
    wake_ = -1;
  }
}

void ConnectionFront::Adopt(int fd) {
  if (!running_) return CloseSocket(fd);
  if (counters_->http_connections_open >= limits_.max_connections) {
    ++counters_->http_connections_refused;
    return AnswerAndClose(fd, 503, "too many connections");
  }
  if (!HoldAddress(fd)) {
    ++counters_->http_address_refused;
    return AnswerAndClose(fd, 503, "too many connections from this address");
  }
  ++counters_->http_connections_open;
  SetNonBlocking(fd);
  {
    std::lock_guard lock(handover_mutex_);
    handovers_.push_back({fd, "", 0});
  }
  const uint64_t one = 1;
  (void)!::write(wake_, &one, sizeof one);
}

void ConnectionFront::Done(int fd, std::string unread, int served, bool keep_alive) {
  if (!keep_alive || !running_) {
    ReleaseAddress(fd);
    CloseSocket(fd);
    --counters_->http_connections_open;
    return;
  }
  {
    std::lock_guard lock(handover_mutex_);
    handovers_.push_back({fd, std::move(unread), served});
  }
  const uint64_t one = 1;
  (void)!::write(wake_, &one, sizeof one);
}

void ConnectionFront::Loop() {
  epoll_event events[kMaxEvents];
  while (running_) {
    int timeout_ms = 1000;
    if (!deadlines_.empty()) {
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadlines_.begin()->first -
                                                                     SteadyClock::now());
      timeout_ms = static_cast<int>(std::clamp<long long>(left.count(), 0, 1000));
    }
    const int n = ::epoll_wait(epoll_, events, kMaxEvents, timeout_ms);
    for (int i = 0; i < n && running_; ++i) {
      if (events[i].data.fd == wake_) {
        uint64_t count = 0;
        (void)!::read(wake_, &count, sizeof count);
        TakeHandovers();
        continue;
      }
      const auto it = connections_.find(events[i].data.fd);
      if (it != connections_.end()) OnReadable(it->second);
    }
    ExpireDeadlines();
  }
}

void ConnectionFront::TakeHandovers() {
  std::vector<Handover> taken;
  {
    std::lock_guard lock(handover_mutex_);
    taken.swap(handovers_);
  }
  for (Handover& h : taken) Add(std::move(h));
}

void ConnectionFront::Add(Handover h) {
  Connection& c = connections_[h.fd];
  c.fd = h.fd;
  c.buffer = std::move(h.unread);
  c.served = h.served;
  c.idle = c.buffer.empty();
  buffered_bytes_ += c.buffer.size();
  // A new connection must send its request within the header time-out; a kept-alive one may idle.
  const bool kept_alive = c.idle && c.served > 0;
  SetDeadline(c, SteadyClock::now() +
                     Seconds(kept_alive ? limits_.keep_alive_timeout_s : limits_.header_timeout_s));
  epoll_event e{};
  e.events = EPOLLIN | EPOLLRDHUP;
  e.data.fd = c.fd;
  if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, c.fd, &e) != 0) return Forget(c, true);
  if (!c.buffer.empty()) Advance(c);  // a pipelined request may be complete already
}

void ConnectionFront::OnReadable(Connection& c) {
  const size_t limit = c.head_bytes > 0 ? c.head_bytes + c.body_bytes : head_limits_.max_bytes + 1;
  const size_t max_buffered = static_cast<size_t>(limits_.max_buffered_mb) << 20;
  char chunk[kReadChunk];
  bool peer_closed = false;
  while (c.buffer.size() < limit) {
    const size_t room = std::min(limit - c.buffer.size(), sizeof chunk);
    if (buffered_bytes_ + room > max_buffered) {
      return Refuse(c, 503, "the server holds too many unfinished requests", &counters_->http_busy);
    }
    const ssize_t n = ::recv(c.fd, chunk, room, 0);
    if (n > 0) {
      c.buffer.append(chunk, static_cast<size_t>(n));
      buffered_bytes_ += static_cast<size_t>(n);
      if (c.idle) {
        c.idle = false;
        SetDeadline(c, SteadyClock::now() + Seconds(limits_.header_timeout_s));
      }
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    peer_closed = true;  // end of stream or an error
    break;
  }
  const int fd = c.fd;
  Advance(c);
  // A peer that closed its side gets its complete request answered; otherwise it is gone.
  const auto still = connections_.find(fd);
  if (peer_closed && still != connections_.end()) Forget(still->second, true);
}

void ConnectionFront::Advance(Connection& c) {
  if (c.head_bytes == 0) {
    const HeadEnd end = FindHeadEnd(c.buffer, head_limits_);
    switch (end.state) {
      case HeadState::kIncomplete:
        return;
      case HeadState::kTooLarge:
        return Refuse(
            c, 431, "request head larger than " + std::to_string(head_limits_.max_bytes) + " bytes",
            &counters_->http_heads_too_large);
      case HeadState::kTooManyFields:
        return Refuse(c, 431,
                      "more than " + std::to_string(head_limits_.max_fields) + " header fields",
                      &counters_->http_heads_too_large);
      case HeadState::kComplete:
        break;
    }
    Result<RequestHead> head = ParseHead(std::string_view(c.buffer).substr(0, end.length));
    if (!head.ok())
      return Refuse(c, 400, head.status().message(), &counters_->http_requests_refused);
    size_t body = 0;
    if (auto refusal = CheckRequest(*head, policy_, &body)) {
      return Refuse(c, refusal->status, refusal->message, &counters_->http_requests_refused);
    }
    c.head_bytes = end.length;
    c.body_bytes = body;
    c.stream = head->method == "GET" && head->Path() == "/api/events";
    const std::string* expect = head->Field("expect");
    if (expect != nullptr && body > 0 && c.buffer.size() < c.head_bytes + body) {
      (void)SendBefore(c.fd, "HTTP/1.1 100 Continue\r\n\r\n", SteadyClock::now());
    }
  }
  if (c.buffer.size() < c.head_bytes + c.body_bytes) return;
  Dispatch(c);
}

void ConnectionFront::Dispatch(Connection& c) {
  const int fd = c.fd;
  const bool stream = c.stream;
  ReadyRequest request{fd, std::move(c.buffer), c.served};
  c.buffer.clear();
  buffered_bytes_ -= request.bytes.size();
  Forget(c, false);  // no longer the front's; the stream hub counts its own
  if (stream) {
    ReleaseAddress(fd);
    return to_streams_(fd);
  }
  ++counters_->http_connections_open;  // still open: a worker has it
  if (!to_workers_(request)) {
    ++counters_->http_busy;
    --counters_->http_connections_open;
    ReleaseAddress(fd);
    AnswerAndClose(fd, 503, "busy: too many requests waiting");
  }
}

void ConnectionFront::Refuse(Connection& c, int status, const std::string& message,
                             std::atomic<uint64_t>* counter) {
  ++*counter;
  ++counters_->http_requests;
  if (status < 500) ++counters_->http_rejected;
  const int fd = c.fd;
  Forget(c, false);
  ReleaseAddress(fd);
  AnswerAndClose(fd, status, message);
}

void ConnectionFront::Forget(Connection& c, bool close_socket) {
  const int fd = c.fd;
  ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
  deadlines_.erase({c.deadline, fd});
  buffered_bytes_ -= std::min(buffered_bytes_, c.buffer.size());
  if (close_socket) {
    ReleaseAddress(fd);
    CloseSocket(fd);
  }
  --counters_->http_connections_open;
  connections_.erase(fd);
}

bool ConnectionFront::HoldAddress(int fd) {
  if (limits_.max_connections_per_address == 0) return true;
  std::string address = PeerAddress(fd);
  std::lock_guard lock(address_mutex_);
  int& held = held_by_address_[address];
  if (held >= limits_.max_connections_per_address) return false;
  ++held;
  address_of_[fd] = std::move(address);
  return true;
}

void ConnectionFront::ReleaseAddress(int fd) {
  std::lock_guard lock(address_mutex_);
  const auto it = address_of_.find(fd);
  if (it == address_of_.end()) return;
  const auto held = held_by_address_.find(it->second);
  if (held != held_by_address_.end() && --held->second <= 0) held_by_address_.erase(held);
  address_of_.erase(it);
}

void ConnectionFront::SetDeadline(Connection& c, SteadyClock::time_point deadline) {
  deadlines_.erase({c.deadline, c.fd});
  c.deadline = deadline;
  deadlines_.insert({deadline, c.fd});
}

void ConnectionFront::ExpireDeadlines() {
  const auto now = SteadyClock::now();
  while (!deadlines_.empty() && deadlines_.begin()->first <= now) {
    const int fd = deadlines_.begin()->second;
    deadlines_.erase(deadlines_.begin());
    const auto it = connections_.find(fd);
    if (it == connections_.end()) continue;
    Connection& c = it->second;
    if (c.idle && c.served > 0) {
      Forget(c, true);  // an idle kept-alive connection: closed quietly
    } else {
      Refuse(c, 408, "the request did not arrive in time (http.header_timeout_s)",
             &counters_->http_head_timeouts);
    }
  }
}

}  // namespace fleetloc::fleet_supervisor
