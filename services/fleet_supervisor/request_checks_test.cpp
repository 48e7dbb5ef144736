// Request checks: Host allow-list (DNS rebinding), NUL and control bytes in the target, byte
// ranges, body lengths and Expect.
#include "fleet_supervisor/request_checks.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet_supervisor {
namespace {

RequestHead Head(const std::string& text) { return std::move(ParseHead(text)).value(); }

TEST(RequestChecks, DefaultHostsAreTheLocalNamesAndTheBindAddress) {
  EXPECT_EQ(DefaultAllowedHosts("127.0.0.1"),
            (std::vector<std::string>{"localhost", "127.0.0.1", "::1"}));
  EXPECT_EQ(DefaultAllowedHosts("10.1.2.3"),
            (std::vector<std::string>{"localhost", "127.0.0.1", "::1", "10.1.2.3"}));
  EXPECT_EQ(DefaultAllowedHosts("0.0.0.0").size(), 3u);
  const auto allowed = DefaultAllowedHosts("127.0.0.1");
  for (const char* host :
       {"localhost", "localhost:8080", "LocalHost:80", "127.0.0.1:8080", "[::1]:8080", "[::1]"}) {
    EXPECT_TRUE(HostAllowed(host, allowed)) << host;
  }
  for (const char* host :
       {"evil.example", "evil.example:8080", "127.0.0.2", "localhost.evil.example", "", "[::1"}) {
    EXPECT_FALSE(HostAllowed(host, allowed)) << host;
  }
  EXPECT_TRUE(HostAllowed("anything:1", {"*"}));
}

TEST(RequestChecks, ARebindingHostIsMisdirected) {
  RequestPolicy policy;
  policy.allowed_hosts = DefaultAllowedHosts("127.0.0.1");
  size_t body = 0;
  const auto refusal = CheckRequest(
      Head("GET /api/fleet HTTP/1.1\r\nHost: attacker.example:8080\r\n\r\n"), policy, &body);
  ASSERT_TRUE(refusal.has_value());
  EXPECT_EQ(refusal->status, 421);
  EXPECT_FALSE(
      CheckRequest(Head("GET /api/fleet HTTP/1.1\r\nHost: localhost:8080\r\n\r\n"), policy, &body));
  EXPECT_EQ(CheckRequest(Head("GET /api/fleet HTTP/1.1\r\n\r\n"), policy, &body)->status, 400);
  EXPECT_EQ(CheckRequest(Head("GET / HTTP/1.1\r\nHost: localhost\r\nHost: localhost\r\n\r\n"),
                         policy, &body)
                ->status,
            400);
}

TEST(RequestChecks, NulAndControlBytesInTheTargetAreRefused) {
  RequestPolicy policy;
  policy.allowed_hosts = {"localhost"};
  size_t body = 0;
  for (const char* target : {"/index.html%00.js", "/app.js%00", "/a%00b", "relative"}) {
    const auto refusal = CheckRequest(
        Head(std::string("GET ") + target + " HTTP/1.1\r\nHost: localhost\r\n\r\n"), policy, &body);
    ASSERT_TRUE(refusal.has_value()) << target;
    EXPECT_EQ(refusal->status, 400) << target;
  }
  EXPECT_FALSE(
      CheckRequest(Head("GET /a%20b?q=%41 HTTP/1.1\r\nHost: localhost\r\n\r\n"), policy, &body));
}

TEST(RequestChecks, RangesAreCountedAndLimited) {
  EXPECT_EQ(RangeCount("bytes=0-99"), 1);
  EXPECT_EQ(RangeCount("bytes=0-1, 5-6,-9"), 3);
  EXPECT_EQ(RangeCount("items=0-1"), -1);
  EXPECT_EQ(RangeCount("bytes=0-1,,2-3"), -1);
  RequestPolicy policy;
  policy.allowed_hosts = {"localhost"};
  size_t body = 0;
  std::string many = "bytes=0-0";
  for (int i = 1; i < 900; ++i)
    many.append(",").append(std::to_string(i)).append("-").append(std::to_string(i));
  EXPECT_EQ(
      CheckRequest(Head("GET /app.js HTTP/1.1\r\nHost: localhost\r\nRange: " + many + "\r\n\r\n"),
                   policy, &body)
          ->status,
      416);
  EXPECT_FALSE(CheckRequest(
      Head("GET /app.js HTTP/1.1\r\nHost: localhost\r\nRange: bytes=0-99\r\n\r\n"), policy, &body));
}

TEST(RequestChecks, BodiesNeedABoundedContentLength) {
  RequestPolicy policy;
  policy.allowed_hosts = {"localhost"};
  policy.max_body_bytes = 1000;
  size_t body = 0;
  const std::string post = "POST /api/remap HTTP/1.1\r\nHost: localhost\r\n";
  EXPECT_FALSE(CheckRequest(Head(post + "Content-Length: 12\r\n\r\n"), policy, &body));
  EXPECT_EQ(body, 12u);
  EXPECT_EQ(CheckRequest(Head(post + "Content-Length: 1001\r\n\r\n"), policy, &body)->status, 413);
  EXPECT_EQ(CheckRequest(Head(post + "Content-Length: 1x\r\n\r\n"), policy, &body)->status, 400);
  EXPECT_EQ(
      CheckRequest(Head(post + "Content-Length: 1\r\nContent-Length: 2\r\n\r\n"), policy, &body)
          ->status,
      400);
  EXPECT_EQ(CheckRequest(Head(post + "Transfer-Encoding: chunked\r\n\r\n"), policy, &body)->status,
            411);
  EXPECT_EQ(CheckRequest(Head(post + "Expect: 200-ok\r\n\r\n"), policy, &body)->status, 417);
  EXPECT_FALSE(CheckRequest(Head(post + "Expect: 100-continue\r\nContent-Length: 5\r\n\r\n"),
                            policy, &body));
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
