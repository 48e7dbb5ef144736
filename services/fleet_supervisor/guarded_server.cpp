// GuardedServer: httplib behind the connection front.
#include "fleet_supervisor/guarded_server.h"

#include <sys/socket.h>

#include <cerrno>

#include "fleet_supervisor/request_stream.h"

namespace fleetloc::fleet_supervisor {
namespace {

constexpr int kListenBacklog = 4096;

// httplib's accept loop enqueues one task per accepted socket; this queue runs it at once on the
// accept thread, where process_and_close_socket only hands the socket to the front.
class InlineTaskQueue : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

std::chrono::milliseconds Seconds(double s) {
  return std::chrono::milliseconds(static_cast<long long>(s * 1000));
}

}  // namespace

GuardedServer::GuardedServer(const HttpLimits& limits, RequestPolicy policy, EventStream* stream,
                             SupervisorCounters* counters)
    : limits_(limits), counters_(counters) {
  new_task_queue = [] { return new InlineTaskQueue; };
  hub_ = std::make_unique<StreamHub>(stream, limits, counters);
  workers_ = std::make_unique<WorkerPool<ReadyRequest>>(
      limits.workers, static_cast<size_t>(limits.queue), [this](ReadyRequest& r) { Serve(r); },
      [this](ReadyRequest& r) { front_->Done(r.fd, "", r.served, false); });
  front_ = std::make_unique<ConnectionFront>(
      limits, std::move(policy), [this](ReadyRequest& r) { return workers_->TryPush(r); },
      [this](int fd) { hub_->Adopt(fd); }, counters);
}

GuardedServer::~GuardedServer() { StopGuards(); }

int GuardedServer::Bind(const std::string& host, int port, int* error) {
  // httplib's default sets SO_REUSEPORT, with which a second server on the same port binds too and
  // the kernel splits the connections between them. SO_REUSEADDR alone still allows a restart
  // while old connections linger in TIME_WAIT, but not two listeners.
  set_socket_options([](socket_t sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  errno = 0;
  const int bound = port == 0 ? bind_to_any_port(host) : (bind_to_port(host, port) ? port : -1);
  if (error) *error = bound > 0 ? 0 : errno;
  if (bound > 0) ::listen(svr_sock_, kListenBacklog);  // deepens httplib's backlog of 5
  return bound;
}

Status GuardedServer::StartGuards() {
  FLEETLOC_RETURN_IF_ERROR(hub_->Start());
  return front_->Start();
}

void GuardedServer::StopGuards() {
  if (front_) front_->Stop();
  if (workers_) workers_->Stop();
  if (hub_) hub_->Stop();
}

bool GuardedServer::process_and_close_socket(socket_t sock) {
  front_->Adopt(sock);
  return true;
}

void GuardedServer::Serve(ReadyRequest& r) {
  const auto now = SteadyClock::now();
  // The front read the whole request; a short grace covers nothing but pipelined leftovers.
  RequestStream stream(r.fd, std::move(r.bytes), now + std::chrono::milliseconds(100),
                       now + Seconds(limits_.write_timeout_s));
  const bool last = r.served + 1 >= limits_.max_requests_per_connection;
  bool connection_closed = false;
  const bool answered = process_request(stream, last, connection_closed, nullptr);
  front_->Done(r.fd, stream.TakeUnread(), r.served + 1, answered && !last && !connection_closed);
}

}  // namespace fleetloc::fleet_supervisor
