// The fleet across hosts (MultiHostFleet: five network namespaces, the shipped multi-host DDS
// configuration) with the mosaic split between two map servers: the vehicles track as they cross
// the boundary between the servers' regions; with packet loss and delay between the hosts; when
// a map server, the supervisor or an agent is killed (SIGKILL) and restarted. Nothing a server
// acknowledged is lost, both mosaic replicas store every patch, every vehicle returns to tracking.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "multihost_fleet.h"

namespace fleetloc {
namespace {

using testing::Eventually;
using testing::MultiHostFleet;

double WallNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void Drive(double seconds) { std::this_thread::sleep_for(std::chrono::duration<double>(seconds)); }

// Every pose the supervisor recorded for each vehicle since `from` is `tracking`; returns how
// many vehicles crossed the servers' boundary meanwhile.
int ExpectTrackingSince(const MultiHostFleet& fleet, double from) {
  int crossed = 0;
  for (const char* vehicle : MultiHostFleet::kVehicles) {
    const auto [locks, xs] = fleet.Trace(vehicle, from);
    EXPECT_GT(locks.size(), 20u) << vehicle << ": too few poses recorded";
    EXPECT_EQ(std::count(locks.begin(), locks.end(), "tracking"), static_cast<long>(locks.size()))
        << vehicle << " did not track throughout";
    if (xs.empty()) continue;
    const auto [lo, hi] = std::minmax_element(xs.begin(), xs.end());
    crossed += *lo < MultiHostFleet::kBoundaryX && *hi > MultiHostFleet::kBoundaryX;
    std::printf("%s: %zu poses, x in [%.3f, %.3f] m\n", vehicle, locks.size(), *lo, *hi);
  }
  return crossed;
}

std::map<std::string, nlohmann::json> ServicesById(const nlohmann::json& status) {
  std::map<std::string, nlohmann::json> by_id;
  if (status.is_object()) {
    for (const nlohmann::json& s : status["services"]) by_id[s.value("id", "")] = s;
  }
  return by_id;
}

TEST(MultiHost, TheFleetTracksAcrossHostsWithTheMosaicSplitBetweenTwoServers) {
  MultiHostFleet fleet("multihost_split");
  if (!fleet.skip.empty()) GTEST_SKIP() << fleet.skip;
  ASSERT_TRUE(Eventually([&] { return fleet.AllTracking(); }, 90)) << "the fleet did not come up";
  const double from = WallNow();
  Drive(30);
  EXPECT_GE(ExpectTrackingSince(fleet, from), 1) << "no vehicle crossed between the servers' regions";

  const nlohmann::json status = fleet.Status();
  auto services = ServicesById(status);
  for (const char* id : {"ms-west", "ms-east"}) {
    ASSERT_TRUE(services.count(id)) << status.dump(1);
    std::printf("%s: %s\n", id, services[id]["counters"].dump().c_str());
    EXPECT_GT(services[id]["counters"].value("tiles_served", 0), 0) << id;
    EXPECT_GT(services[id]["counters"].value("tiles_not_owned", 0), 0) << id << " saw no request for the other's tiles";
  }
  EXPECT_EQ(status["mosaics"].size(), 2u);
  for (const nlohmann::json& v : status["vehicles"]) {
    const auto issues = v["health"]["issues"].get<std::vector<std::string>>();
    EXPECT_EQ(std::count(issues.begin(), issues.end(), "tile_timeouts"), 0) << v.dump();
  }
  fleet.StopAll();
}

}  // namespace
}  // namespace fleetloc
