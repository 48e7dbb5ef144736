// The fleet supervisor's HTTP API against bad input (malformed requests, unknown vehicles, missing
// or wrong tokens, huge query ranges, oversized bodies, peers of another wire version: a clear
// 4xx JSON error, counted, never a crash) and across a restart (history and vehicles survive).
// Eigen (through pose_messages.h) before httplib: <resolv.h> defines a macro `_res` that
// breaks Eigen's headers when included first.
// clang-format off: Eigen before httplib (<resolv.h> defines `_res`, a name Eigen's headers use)
#include <Eigen/Core>
// clang-format on
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <future>
#include <nlohmann/json.hpp>

#include "fake_vehicle.h"
#include "supervisor_fixture.h"
#include "transport/pose_messages.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

constexpr uint32_t kDomain = 101;
using nlohmann::json;

using testing::FakeVehicle;

// Status and the "error" member of a JSON error body ("" when the body has none).
std::pair<int, std::string> Status(const httplib::Result& r) {
  if (!r) return {-1, "no answer"};
  const json body = json::parse(r->body, nullptr, false);
  return {r->status, body.is_object() ? body.value("error", "") : ""};
}

// Sends raw bytes and returns the first line of the answer.
std::string RawRequest(int port, const std::string& bytes) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) return "connect failed";
  (void)::write(fd, bytes.data(), bytes.size());
  char buffer[256] = {};
  const ssize_t n = ::read(fd, buffer, sizeof buffer - 1);
  ::close(fd);
  const std::string answer(buffer, n > 0 ? static_cast<size_t>(n) : 0);
  return answer.substr(0, answer.find("\r\n"));
}

TEST(SupervisorHttp, BadInputGetsAClearFourHundredAndIsCounted) {
  testing::ScratchDir dir("supervisor_http_bad");
  testing::SupervisorProcess supervisor(dir.path(), kDomain, "tok-5551-5551-5551");
  auto participant = transport::Participant::Create(kDomain);
  ASSERT_TRUE(participant.ok());
  FakeVehicle vehicle(*participant, "agv-h1");
  httplib::Client http("127.0.0.1", supervisor.port());
  ASSERT_TRUE(testing::Eventually([&] {
    vehicle.Publish(0.5);
    auto r = http.Get("/api/vehicles/agv-h1");
    return r && r->status == 200;
  })) << supervisor.log();

  const std::pair<std::string, int> gets[] = {
      {"/api/vehicles/agv-zz", 404},
      {"/api/vehicles/bad*id", 400},
      {"/api/vehicles/much-too-long-vehicle-id", 400},
      {"/api/vehicles/agv-zz/history", 404},
      {"/api/vehicles/agv-h1/history?from=abc", 400},
      {"/api/vehicles/agv-h1/history?from=nan", 400},
      {"/api/vehicles/agv-h1/history?from=0&to=1e12", 400},  // a huge range
      {"/api/vehicles/agv-h1/history?from=20&to=10", 400},
      {"/api/vehicles/agv-h1/history?max_points=1", 400},
      {"/api/vehicles/agv-h1/history?max_points=10.5", 400},
      {"/api/vehicles/agv-h1/history?max_points=99999999", 400},
      {"/api/alerts?limit=0", 400},
      {"/api/alerts?vehicle=a*", 400},
      {"/api/tiles/x/0/0.png", 400},
      {"/api/tiles/0/-1/0.png", 400},
      {"/api/tiles/0/0/0.png", 503},  // no map server on this domain
      {"/api/mosaic", 503},
      {"/api/nothing-here", 404},
  };
  for (const auto& [path, expected] : gets) {
    const auto [status, error] = Status(http.Get(path));
    EXPECT_EQ(status, expected) << path;
    EXPECT_FALSE(error.empty()) << path << ": no JSON error message";
  }
  const std::string good = R"({"region": [0, 0, 0.1, 0.1], "mode": "blend"})";
  const httplib::Headers right = {{"Authorization", "Bearer tok-5551-5551-5551"}};
  EXPECT_EQ(Status(http.Post("/api/remap", good, "application/json")).first, 401);
  EXPECT_EQ(
      Status(http.Post("/api/remap", {{"Authorization", "Bearer nope"}}, good, "application/json"))
          .first,
      403);
  EXPECT_EQ(Status(http.Post("/api/remap", {{"Authorization", "tok-5551-5551-5551"}}, good,
                             "application/json"))
                .first,
            401);
  EXPECT_EQ(Status(http.Get("/api/auth", {{"Authorization", "Bearer nope"}})).first, 403);
  EXPECT_EQ(Status(http.Get("/api/auth", right)).first, 200);
  for (const std::string bad :
       {"{not json", "[1,2]", R"({"region": [0, 0, 1]})", R"({"region": [0, 0, "a", 1]})",
        R"({"region": [0, 0, 1, 1], "mode": "melt"})", R"({"region": [1, 1, 0, 0]})"}) {
    const auto [status, error] = Status(http.Post("/api/remap", right, bad, "application/json"));
    EXPECT_TRUE(status == 400 || status == 503) << bad << " -> " << status;
    EXPECT_FALSE(error.empty()) << bad;
  }
  EXPECT_EQ(Status(http.Post("/api/remap", right, good, "application/json")).first,
            503);  // no map server
  // A mistyped key is refused by name, not ignored (issue 22; it had started a blend re-map).
  const auto [typo_status, typo_error] =
      Status(http.Post("/api/remap", right, R"({"region": [0, 0, 0.1, 0.1], "mdoe": "replace"})",
                       "application/json"));
  EXPECT_EQ(typo_status, 400);
  EXPECT_NE(typo_error.find("'mdoe'"), std::string::npos) << typo_error;
  EXPECT_EQ(
      Status(http.Post("/api/remap", right, std::string(100000, ' '), "application/json")).first,
      413);
  EXPECT_EQ(RawRequest(supervisor.port(), "GARBAGE\r\n\r\n").substr(0, 12), "HTTP/1.1 400");

  // A peer of another wire version is rejected and counted, not shown.
  FakeVehicle stranger(*participant, "agv-old");
  ASSERT_TRUE(testing::Eventually([&] {
    stranger.Publish(0.1, 99);
    auto stats = http.Get("/api/stats");
    return stats && json::parse(stats->body).value("rejected_samples", 0) > 0;
  }));
  EXPECT_EQ(http.Get("/api/vehicles/agv-old")->status, 404);
  auto stats = http.Get("/api/stats");
  ASSERT_TRUE(stats);
  EXPECT_GE(json::parse(stats->body).value("http_rejected", 0), 25) << stats->body;
  EXPECT_EQ(http.Get("/api/fleet")->status, 200) << "still serving";

  // fleetctl status hears the vehicle and the supervisor over DDS.
  auto status = std::async(std::launch::async, [] {
    return testing::RunFleetctl("status --json --wait 1.5 --domain " + std::to_string(kDomain));
  });
  while (status.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready)
    vehicle.Publish(0.6);
  const testing::CommandResult r = status.get();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json fleet = json::parse(r.out);
  EXPECT_EQ(fleet["summary"].value("vehicles", 0), 1) << r.out;
  EXPECT_EQ(fleet["vehicles"][0].value("id", ""), "agv-h1");
  EXPECT_EQ(fleet["services"][0].value("kind", ""), "fleet_supervisor");
}

TEST(SupervisorHttp, HistoryAndVehiclesSurviveARestart) {
  testing::ScratchDir dir("supervisor_http_restart");
  auto participant = transport::Participant::Create(kDomain);
  ASSERT_TRUE(participant.ok());
  {
    testing::SupervisorProcess supervisor(dir.path(), kDomain, "tok-1-tok-1-tok-1");
    FakeVehicle vehicle(*participant, "agv-r1");
    httplib::Client http("127.0.0.1", supervisor.port());
    for (int i = 0; i < 60; ++i) {  // 3 s at 20 Hz: several stored poses (one per second)
      vehicle.Publish(0.1 + 0.01 * i);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ASSERT_EQ(http.Get("/api/vehicles/agv-r1")->status, 200);
  }  // SIGTERM: the last rows are flushed
  testing::SupervisorProcess supervisor(dir.path(), kDomain, "tok-1-tok-1-tok-1");
  httplib::Client http("127.0.0.1", supervisor.port());
  auto vehicle = http.Get("/api/vehicles/agv-r1");
  ASSERT_TRUE(vehicle);
  ASSERT_EQ(vehicle->status, 200) << vehicle->body;
  EXPECT_NEAR(json::parse(vehicle->body)["pose"].value("x", 0.0), 0.69, 0.05);
  auto history = http.Get("/api/vehicles/agv-r1/history");
  ASSERT_TRUE(history);
  const json h = json::parse(history->body);
  EXPECT_GE(h["poses"]["t"].size(), 3u) << history->body;
  EXPECT_GE(h["health"]["t"].size(), 3u);
  // Not heard from since the restart: silent, with a stored alert.
  ASSERT_TRUE(testing::Eventually(
      [&] {
        auto alerts = http.Get("/api/alerts?active=1&vehicle=agv-r1");
        return alerts && json::parse(alerts->body)["history"].size() == 1;
      },
      10))
      << http.Get("/api/alerts")->body;
}

}  // namespace
}  // namespace fleetloc
