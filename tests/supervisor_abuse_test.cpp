// The fleet supervisor's HTTP side against hostile clients over real sockets: idle sockets, live
// streams that never read, slow senders trickling an endless head and a flood of header lines,
// all at once, while an operator keeps using the API — every /api/fleet and POST /api/remap is
// answered by its handler, and the supervisor's memory stays bounded. Then the single refusals:
// a foreign Host (DNS rebinding), %00 in a path, too many byte ranges, too many streams or
// connections, and wrong tokens (backoff). Scaled-up numbers and latencies: `fleetctl bench
// supervisor-abuse` (docs/benchmarks.md).
// clang-format off
#include "supervisor_fixture.h"  // Eigen before httplib (<resolv.h> defines `_res`)
#include <httplib.h>
// clang-format on

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "harness/supervisor/http_abuse.h"

namespace fleetloc {
namespace {

constexpr uint32_t kDomain = 103;
constexpr const char* kToken = "abuse-test-token-0123";
using nlohmann::json;

// A socket connected to the supervisor on loopback from the local address `from` (another
// 127.x.y.z is another client address), or -1.
int ConnectFrom(int port, const char* from = "127.0.0.1") {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in source{};
  source.sin_family = AF_INET;
  ::inet_pton(AF_INET, from, &source.sin_addr);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval timeout{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&source), sizeof source) != 0 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// The first line of the answer to raw `bytes` (the connection closes or 5 s pass).
std::string FirstLine(int port, const std::string& bytes, const char* from = "127.0.0.1") {
  const int fd = ConnectFrom(port, from);
  if (fd < 0) return "connect failed";
  (void)!::write(fd, bytes.data(), bytes.size());
  std::string answer;
  char buffer[4096];
  for (ssize_t n;
       answer.find("\r\n") == std::string::npos && (n = ::read(fd, buffer, sizeof buffer)) > 0;) {
    answer.append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  return answer.substr(0, answer.find("\r\n"));
}

// The supervisor's counters ({} when it does not answer).
json Stats(httplib::Client& http) {
  auto r = http.Get("/api/stats");
  const json stats = r ? json::parse(r->body, nullptr, false) : json();
  return stats.is_object() ? stats : json::object();
}

std::string WriteConfig(const std::filesystem::path& dir, const json& http) {
  std::string path = (dir / "supervisor.json").string();
  std::ofstream(path) << json{{"http", http}}.dump();
  return path;
}

TEST(SupervisorAbuse, TheApiKeepsAnsweringWhileHostileClientsHoldIdleStreamSlowAndFloodingSockets) {
  testing::ScratchDir dir("supervisor_abuse_load");
  testing::SupervisorProcess supervisor(dir.path(), kDomain, kToken);
  httplib::Client http("127.0.0.1", supervisor.port());
  http.set_connection_timeout(10);
  http.set_read_timeout(10);
  ASSERT_TRUE(http.Get("/api/fleet")) << supervisor.log();
  const double rss_before = runtime::UsageOf(supervisor.pid()).peak_rss_mb;

  bench::AbuseOptions options;
  options.port = supervisor.port();
  options.idle = 300;
  options.streams = 40;
  options.slow = 20;
  options.flood_mb = 20;
  bench::HttpAbuse abuse(options);
  abuse.Start();
  std::this_thread::sleep_for(std::chrono::seconds(1));  // let the attackers take their sockets
  const httplib::Headers maintainer = {{"Authorization", std::string("Bearer ") + kToken}};
  const std::string remap = R"({"region": [0, 0, 0.1, 0.1], "mode": "blend"})";
  int fleet_ok = 0, remap_handled = 0;
  long long open_streams = 0;
  for (int i = 0; i < 40; ++i) {
    auto fleet = http.Get("/api/fleet");
    fleet_ok += fleet && fleet->status == 200;
    // No map server on this domain: the handler itself answers 503 after checking the token.
    auto started = http.Post("/api/remap", maintainer, remap, "application/json");
    remap_handled += started && started->status == 503 &&
                     started->body.find("no map server is listening") != std::string::npos;
    open_streams = std::max<long long>(open_streams, Stats(http).value("http_streams_open", 0LL));
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
  }
  const json stats = Stats(http);
  abuse.Stop();
  const bench::AbuseStats attack = abuse.stats();

  EXPECT_EQ(fleet_ok, 40) << supervisor.log();
  EXPECT_EQ(remap_handled, 40);
  EXPECT_GE(attack.flood_mb_sent, 19.0);
  EXPECT_EQ(open_streams, 40);  // every stream held, none refused (max_streams 256)
  EXPECT_EQ(attack.streams_refused, 0);
  EXPECT_GE(stats.value("http_head_timeouts", 0), 250)
      << stats;  // idle and slow sockets cut at 5 s
  // Each flooding connection is cut after 16 KiB (what it sent beyond sat in kernel buffers).
  EXPECT_GE(stats.value("http_heads_too_large", 0), 1) << stats;
  // 20 MB of headers and hundreds of sockets cost the supervisor little memory.
  const double rss_after = runtime::UsageOf(supervisor.pid()).peak_rss_mb;
  EXPECT_LT(rss_after - rss_before, 64.0)
      << "peak RSS " << rss_before << " -> " << rss_after << " MB";
}

TEST(SupervisorAbuse, ForeignHostsNulBytesRangesAndSurplusConnectionsAreRefused) {
  testing::ScratchDir dir("supervisor_abuse_refusals");
  const std::string config = WriteConfig(
      dir.path(), {{"max_connections", 32}, {"max_streams", 2}, {"header_timeout_s", 1.0}});
  testing::SupervisorProcess supervisor(dir.path(), kDomain, kToken, {"--config", config});
  const int port = supervisor.port();
  const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
  EXPECT_EQ(FirstLine(port, "GET /api/fleet HTTP/1.1\r\n" + host + "\r\n"), "HTTP/1.1 200 OK");
  EXPECT_EQ(FirstLine(port, "GET /api/fleet HTTP/1.1\r\nHost: rebound.attacker.example\r\n\r\n"),
            "HTTP/1.1 421 Misdirected Request");
  EXPECT_EQ(FirstLine(port, "GET /index.html%00.js HTTP/1.1\r\n" + host + "\r\n"),
            "HTTP/1.1 400 Bad Request");
  std::string ranges = "bytes=0-0";
  for (int i = 1; i < 900; ++i)
    ranges.append(",").append(std::to_string(i)).append("-").append(std::to_string(i));
  EXPECT_EQ(
      FirstLine(port, "GET /index.html HTTP/1.1\r\n" + host + "Range: " + ranges + "\r\n\r\n"),
      "HTTP/1.1 416 Range Not Satisfiable");
  EXPECT_EQ(FirstLine(port, "GET /index.html HTTP/1.1\r\n" + host + "Range: bytes=0-9\r\n\r\n"),
            "HTTP/1.1 206 Partial Content");
  std::string fields;
  for (int i = 0; i < 65; ++i) fields.append("X-").append(std::to_string(i)).append(": 1\r\n");
  EXPECT_EQ(FirstLine(port, "GET /api/fleet HTTP/1.1\r\n" + host + fields + "\r\n"),
            "HTTP/1.1 431 Request Header Fields Too Large");
  // A head that never ends is cut at the header time-out.
  EXPECT_EQ(FirstLine(port, "GET /api/fleet HTTP/1.1\r\n" + host), "HTTP/1.1 408 Request Timeout");

  // Two streams at most; the third is refused, and a stream carries snapshots.
  const std::string events = "GET /api/events HTTP/1.1\r\n" + host + "\r\n";
  {
    bench::AbuseOptions options;
    options.port = port;
    options.idle = 0;
    options.streams = 3;
    options.slow = 0;
    options.flood_mb = 0;
    bench::HttpAbuse streams(options);
    streams.Start();
    std::this_thread::sleep_for(std::chrono::seconds(1));
    streams.Stop();
    EXPECT_EQ(streams.stats().streams_answered, 2);
    EXPECT_GE(streams.stats().streams_refused, 1);
  }
  httplib::Client http("127.0.0.1", port);
  ASSERT_TRUE(testing::Eventually([&] { return Stats(http).value("http_streams_open", 1) == 0; }));
  std::string received;
  (void)http.Get("/api/events", [&](const char* data, size_t n) {
    received.append(data, n);
    return received.find("\n\n") == std::string::npos;
  });
  EXPECT_EQ(received.rfind("data: {", 0), 0u) << received.substr(0, 80);

  // Connections beyond max_connections are refused at once.
  bench::AbuseOptions options;
  options.port = port;
  options.idle = 40;
  options.streams = 0;
  options.slow = 0;
  options.flood_mb = 0;
  bench::HttpAbuse idle(options);
  idle.Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  idle.Stop();
  EXPECT_GT(idle.stats().connects, 40);  // the refused ones reconnected
  EXPECT_TRUE(
      testing::Eventually([&] { return Stats(http).value("http_connections_refused", 0) > 0; }));
}

// One address may hold max_connections_per_address sockets; the next one from it is refused at
// once while another address is still answered.
TEST(SupervisorAbuse, OneAddressCannotTakeEveryConnection) {
  testing::ScratchDir dir("supervisor_abuse_per_address");
  const std::string config =
      WriteConfig(dir.path(), {{"max_connections", 64}, {"max_connections_per_address", 6}});
  testing::SupervisorProcess supervisor(dir.path(), kDomain, kToken, {"--config", config});
  const int port = supervisor.port();
  const std::string request =
      "GET /api/fleet HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n";
  httplib::Client http("127.0.0.1", port);
  std::vector<int> idle;
  idle.reserve(6);
  for (int i = 0; i < 6; ++i) idle.push_back(ConnectFrom(port, "127.0.0.2"));
  for (int fd : idle) ASSERT_GE(fd, 0);
  ASSERT_TRUE(
      testing::Eventually([&] { return Stats(http).value("http_connections_open", 0) >= 6; }));
  EXPECT_EQ(FirstLine(port, request, "127.0.0.2"), "HTTP/1.1 503 Service Unavailable");
  EXPECT_EQ(FirstLine(port, request, "127.0.0.3"), "HTTP/1.1 200 OK");
  EXPECT_EQ(FirstLine(port, request), "HTTP/1.1 200 OK");
  EXPECT_GE(Stats(http).value("http_address_refused", 0), 1);
  // Once the address lets its sockets go, it is answered again.
  for (int fd : idle) ::close(fd);
  EXPECT_TRUE(testing::Eventually(
      [&] { return FirstLine(port, request, "127.0.0.2") == "HTTP/1.1 200 OK"; }));
}

TEST(SupervisorAbuse, WrongTokensMakeTheClientWait) {
  testing::ScratchDir dir("supervisor_abuse_tokens");
  testing::SupervisorProcess supervisor(dir.path(), kDomain, kToken);
  httplib::Client http("127.0.0.1", supervisor.port());
  const httplib::Headers wrong = {{"Authorization", "Bearer wrong-token-wrong-token"}};
  const httplib::Headers right = {{"Authorization", std::string("Bearer ") + kToken}};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(http.Get("/api/auth", wrong)->status, 403) << i;
  auto held = http.Get("/api/auth", wrong);
  ASSERT_TRUE(held);
  EXPECT_EQ(held->status, 429);
  EXPECT_EQ(held->get_header_value("Retry-After"), "1");
  EXPECT_EQ(http.Get("/api/auth", right)->status, 429);  // not even the right one is checked now
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  EXPECT_EQ(http.Get("/api/auth", right)->status, 200);
  EXPECT_EQ(Stats(http).value("http_auth_throttled", 0), 2);
  EXPECT_NE(supervisor.log().find("wrong maintainer token from 127.0.0.1"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc
