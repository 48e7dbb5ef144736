// Health that tells the truth (issue 22): a vehicle that stops publishing is STALE in the
// supervisor's fleet summary (not counted as tracking), its health, its alerts and in
// `fleetctl status --supervisor`; /healthz and /readyz answer while the supervisor runs.
// Eigen (through pose_messages.h) before httplib: see supervisor_http_test.cpp.
// clang-format off: these first (Eigen before httplib, whose <resolv.h> defines `_res`).
#include "cli_runner.h"
#include "fake_vehicle.h"
#include "supervisor_fixture.h"
#include "transport/pose_messages.h"
// clang-format on

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace fleetloc {
namespace {

constexpr uint32_t kDomain = 124;
using nlohmann::json;

json Get(httplib::Client& http, const std::string& path, int* status = nullptr) {
  auto r = http.Get(path);
  if (status) *status = r ? r->status : -1;
  return r ? json::parse(r->body, nullptr, false) : json();
}

TEST(SupervisorStale, AVehicleThatStopsPublishingIsStaleEverywhere) {
  testing::ScratchDir dir("supervisor_stale");
  testing::SupervisorProcess supervisor(dir.path(), kDomain, "tok-2222-2222-2222");
  auto participant = transport::Participant::Create(kDomain);
  ASSERT_TRUE(participant.ok());
  testing::FakeVehicle vehicle(*participant, "agv-s1");
  httplib::Client http("127.0.0.1", supervisor.port());

  int status = 0;
  EXPECT_EQ(Get(http, "/healthz", &status), json({{"alive", true}}));
  EXPECT_EQ(status, 200);
  ASSERT_TRUE(testing::Eventually([&] {
    const json ready = Get(http, "/readyz", &status);
    return status == 200 && ready.value("ready", false);
  })) << Get(http, "/readyz").dump();

  // Pose and health are two topics: the pose may be in before the health (health null).
  json fleet;
  ASSERT_TRUE(testing::Eventually([&] {
    vehicle.Publish(0.5);
    fleet = Get(http, "/api/fleet");
    return fleet["summary"].value("tracking", 0) == 1 && fleet["vehicles"][0]["health"].is_object();
  })) << supervisor.log();
  EXPECT_EQ(fleet["vehicles"][0]["health"]["level"], "ok") << fleet.dump();
  const std::string url = "http://127.0.0.1:" + std::to_string(supervisor.port());
  testing::CommandResult live = testing::RunFleetctl("status --json --supervisor " + url);
  ASSERT_EQ(live.exit_code, 0) << live.err;
  EXPECT_EQ(json::parse(live.out)["vehicles"][0]["silent"], false) << live.out;

  // The vehicle stops: after the silence time (3 s by default) it is STALE.
  ASSERT_TRUE(testing::Eventually(
      [&] { return Get(http, "/api/fleet")["summary"].value("silent", 0) == 1; }, 10))
      << Get(http, "/api/fleet").dump();
  fleet = Get(http, "/api/fleet");
  EXPECT_EQ(fleet["summary"]["tracking"], 0) << fleet.dump();
  EXPECT_EQ(fleet["summary"]["vehicles"], 1);
  EXPECT_EQ(fleet["vehicles"][0]["silent"], true);
  EXPECT_EQ(fleet["vehicles"][0]["health"]["level"], "stale");
  EXPECT_EQ(Get(http, "/api/vehicles/agv-s1")["health"]["level"], "stale");
  const json alerts = Get(http, "/api/alerts?active=1&vehicle=agv-s1");
  ASSERT_EQ(alerts["active"].size(), 1u) << alerts.dump();
  EXPECT_EQ(alerts["active"][0]["kind"], "silent");

  testing::CommandResult table = testing::RunFleetctl("status --supervisor " + url);
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("0 tracking"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("1 stale"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("agv-s1      STALE"), std::string::npos) << table.out;
  const json as_json = json::parse(testing::RunFleetctl("status --json --supervisor " + url).out);
  EXPECT_EQ(as_json["vehicles"][0]["health"]["level"], "stale") << as_json.dump();

  // No supervisor there: exit 1 with the URL named; a malformed URL is bad input (2).
  testing::CommandResult none = testing::RunFleetctl("status --supervisor http://127.0.0.1:1");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.err.find("http://127.0.0.1:1"), std::string::npos) << none.err;
  EXPECT_TRUE(
      testing::IsBadInput(testing::RunFleetctl("status --supervisor ftp://x"), {"ftp://x"}));
}

}  // namespace
}  // namespace fleetloc
