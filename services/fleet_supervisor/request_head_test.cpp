// Request heads: the end is found (CRLF or LF), the byte and field limits cut a flood early, and
// the request line and fields are parsed or refused.
#include "fleet_supervisor/request_head.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet_supervisor {
namespace {

TEST(RequestHead, FindsTheEndOfACompleteHead) {
  const std::string head = "GET /api/fleet HTTP/1.1\r\nHost: localhost\r\n\r\n";
  const HeadEnd end = FindHeadEnd(head + "BODY", {});
  EXPECT_EQ(end.state, HeadState::kComplete);
  EXPECT_EQ(end.length, head.size());
  EXPECT_EQ(FindHeadEnd("GET / HTTP/1.1\nHost: x\n\n", {}).state, HeadState::kComplete);
  EXPECT_EQ(FindHeadEnd("GET / HTTP/1.1\r\nHost: x\r\n", {}).state, HeadState::kIncomplete);
  EXPECT_EQ(FindHeadEnd("\r\nGET / HTTP/1.1\r\n\r\n", {}).state, HeadState::kComplete);
}

TEST(RequestHead, AFloodIsCutAtTheLimits) {
  HeadLimits limits;
  limits.max_bytes = 1000;
  limits.max_fields = 10;
  std::string many = "GET / HTTP/1.1\r\n";
  for (int i = 0; i < 11; ++i) many += "X-A: 1\r\n";
  EXPECT_EQ(FindHeadEnd(many, limits).state, HeadState::kTooManyFields);
  const std::string huge = "GET / HTTP/1.1\r\nX-A: " + std::string(2000, 'a');
  EXPECT_EQ(FindHeadEnd(huge, limits).state, HeadState::kTooLarge);
  EXPECT_EQ(FindHeadEnd(huge.substr(0, 999), limits).state, HeadState::kIncomplete);
}

TEST(RequestHead, ParsesTheRequestLineAndFields) {
  auto head = ParseHead(
      "POST /api/remap?x=1 HTTP/1.1\r\nHost: Example:8080\r\nContent-Length:  12 \r\n"
      "X-Two: a\r\nx-two: b\r\n\r\n");
  ASSERT_TRUE(head.ok()) << head.status().message();
  EXPECT_EQ(head->method, "POST");
  EXPECT_EQ(head->target, "/api/remap?x=1");
  EXPECT_EQ(head->Path(), "/api/remap");
  EXPECT_EQ(head->version, "HTTP/1.1");
  ASSERT_NE(head->Field("host"), nullptr);
  EXPECT_EQ(*head->Field("host"), "Example:8080");
  EXPECT_EQ(*head->Field("content-length"), "12");
  EXPECT_EQ(head->Count("x-two"), 2);
  EXPECT_EQ(head->Field("range"), nullptr);
}

TEST(RequestHead, MalformedHeadsAreRefused) {
  for (const char* bad : {"GARBAGE\r\n\r\n", "GET /\r\n\r\n", "GET / HTTP/2.0\r\n\r\n",
                          "GET / HTTP/1.1\r\nno colon here\r\n\r\n",
                          "GET / HTTP/1.1\r\nBad Name: x\r\n\r\n", "G(T / HTTP/1.1\r\n\r\n"}) {
    EXPECT_FALSE(ParseHead(bad).ok()) << bad;
  }
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
