// Re-mapped tiles reach a running vehicle: a tracker_agent drives a live simulated vehicle over a
// floor that changed; patches of the change are folded into mosaic version 2 (`fleetctl remap`);
// the agent drops the tiles the TileUpdate names from its caches, fetches them again at version 2,
// and keeps tracking.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "changed_floor_patches.h"
#include "map_server_fixture.h"
#include "transport/pose_messages.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
using testing::Scene;
constexpr uint32_t kDomain = 87;

TEST(AgentTileUpdate, RemappedTilesAreDroppedAndFetchedAgainAtTheNewVersion) {
  const Scene scene;
  testing::MapServerFixture server("agent_tile_update", scene.old_floor, kDomain);
  const std::string floor = (server.dir() / "new_floor.png").string();
  ASSERT_TRUE(cv::imwrite(floor, scene.new_floor));
  const std::string summary = (server.dir() / "summary.json").string();
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent",
      {"--sim-floor", floor, "--domain", std::to_string(kDomain), "--vehicle-id", "agv-8",
       "--outbox", (server.dir() / "outbox.db").string(), "--summary", summary},
      (server.dir() / "agent.log").string());

  transport::Participant& p = server.participant();
  auto pose_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  auto poses = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *pose_topic, transport::Qos().Reliable().KeepAll());
  int tracked = 0;
  auto count_tracked = [&] {
    (void)poses->TakeAll([&](const fleetloc_VehiclePose& pose, const dds_sample_info_t&) {
      if (pose.lock_state == fleetloc_LOCK_TRACKING) ++tracked;
    });
  };
  ASSERT_TRUE(Eventually(
      [&] {
        count_tracked();
        return tracked > 20;
      },
      30))
      << "agent never tracked";

  // Another vehicle reports the changed floor; the maintainer re-maps the region.
  auto reporter = transport::PatchClient::Create(p, "agv-1");
  ASSERT_TRUE(reporter.ok());
  ASSERT_TRUE(Eventually([&] { return (*reporter)->ServerMatched(); }));
  ASSERT_TRUE(testing::SendPatch(**reporter, testing::ScenePatch(scene, 1, {490, 425}, {})));
  ASSERT_TRUE(testing::SendPatch(**reporter, testing::ScenePatch(scene, 2, {470, 440}, {})));
  size_t acked = 0;
  ASSERT_TRUE(Eventually([&] {
    auto acks = (*reporter)->TakeAcks();
    acked += acks.ok() ? acks->size() : 0;
    return acked >= 2;
  }));
  const testing::CommandResult remap =
      testing::RunFleetctl("remap --domain " + std::to_string(kDomain) + " --region " +
                           testing::RegionAroundChange(scene) + " --mode replace --timeout 120");
  ASSERT_EQ(remap.exit_code, 0) << remap.err;
  ASSERT_EQ(nlohmann::json::parse(remap.out).value("new_version", 0), 2) << remap.out;

  // The agent goes on driving (over the re-mapped crossing too) and tracking.
  count_tracked();
  const int tracked_before = tracked;
  std::this_thread::sleep_for(std::chrono::seconds(5));
  count_tracked();
  EXPECT_GT(tracked - tracked_before, 20) << "tracking after the update";
  EXPECT_EQ(agent.Stop(SIGINT), 0);

  std::ifstream in(summary);
  ASSERT_TRUE(in.good()) << "no summary";
  const nlohmann::json tiles = nlohmann::json::parse(in)["tiles"];
  EXPECT_GT(tiles.value("invalidated", 0), 0) << tiles.dump();
  EXPECT_GT(tiles.value("refreshed", 0), 0)
      << "dropped tiles fetched again at version 2: " << tiles.dump();
}

}  // namespace
}  // namespace fleetloc
