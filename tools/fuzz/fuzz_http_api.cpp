// Fuzz target: the fleet supervisor's HTTP API with raw request bytes (request line, headers,
// query parameters, tokens, JSON bodies) sent over a loopback socket to the real HttpApi, set up
// once per process with an empty fleet, a scratch history and a maintainer token. Every input
// must get an answer (or a closed connection) without a crash or sanitizer report.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <memory>

#include "fleet_supervisor/http_api.h"
#include "fuzz_input.h"
#include "transport/tile_client.h"

namespace {

using namespace fleetloc;
using namespace fleetloc::fleet_supervisor;

constexpr int kDomain = 97;  // nothing else runs here; the tile client never gets an answer

struct Server {
  SupervisorConfig config;
  std::unique_ptr<HistoryStore> history;
  std::unique_ptr<SharedFleet> fleet;
  std::unique_ptr<transport::Participant> participant;
  std::unique_ptr<OverviewTiles> tiles;
  EventStream stream;
  std::unique_ptr<HttpApi> api;
};

Server* StartServer() {
  auto* s = new Server;  // lives for the whole process
  s->config.http_port = 0;
  s->config.supervisor_id = "sup-fuzz";
  s->history = std::move(HistoryStore::Open((fuzz::ScratchDir() / "history.db").string())).value();
  s->fleet =
      std::make_unique<SharedFleet>(s->config.alerts, s->config.trail, s->config.history_period_s);
  s->participant =
      std::make_unique<transport::Participant>(transport::Participant::Create(kDomain).value());
  s->tiles = std::make_unique<OverviewTiles>(
      std::move(transport::TileClient::Create(*s->participant, s->config.supervisor_id)).value(),
      std::size_t{4} << 20, std::chrono::milliseconds(1), 0);
  s->stream.Publish("{}");
  ApiContext context;
  context.config = &s->config;
  context.maintainer_token = "fuzz-token";
  context.fleet = s->fleet.get();
  context.history = s->history.get();
  context.tiles = s->tiles.get();
  context.stream = &s->stream;
  context.start_remap = [](const transport::RemapRequest&) -> Result<uint64_t> {
    return Internal("no map server listens (fuzzing)");
  };
  context.map_server_listening = [] { return false; };
  s->api = std::make_unique<HttpApi>(std::move(context));
  if (!s->api->Start(FLEETLOC_SUPERVISOR_WEB_DIR).ok()) std::abort();
  return s;
}

// Sends `bytes`, half-closes, and reads the answer until the server closes or 200 ms pass.
void Exchange(int port, const std::uint8_t* bytes, std::size_t size) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval timeout{0, 200000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    std::size_t sent = 0;
    while (sent < size) {
      const ssize_t n = ::send(fd, bytes + sent, size - sent, MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += static_cast<std::size_t>(n);
    }
    ::shutdown(fd, SHUT_WR);
    char buffer[4096];
    while (::recv(fd, buffer, sizeof buffer, 0) > 0) {
    }
  }
  ::close(fd);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Server* server = StartServer();
  Exchange(server->api->port(), data, size);
  return 0;
}
