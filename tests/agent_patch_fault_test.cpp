// The agent's patches across a map server outage: a vehicle drives over floor that changed since
// the mosaic was made; it queues patches of it; the map server is killed (SIGKILL) mid-run and
// restarted; the agent keeps tracking from its tile cache meanwhile, and at the end every patch it
// queued is stored by the server exactly once and its outbox is empty — nothing lost.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>

#include "map_server_fixture.h"
#include "mosaic/patch_store.h"
#include "run_io/run.h"
#include "sqlite_value.h"
#include "transport/pose_messages.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 86;

cv::Mat RockFloor() {
  return cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                    cv::IMREAD_GRAYSCALE)(cv::Rect(0, 0, 1536, 1536))
      .clone();
}

// A simulated run over the server's floor with a new 384² marking (another real texture) at the
// route's crossing, so the agent queues patches of it; "" on failure.
std::string ChangedFloorRun(testing::MapServerFixture& server) {
  cv::Mat changed = RockFloor();
  const cv::Mat brick =
      cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/brick.png", cv::IMREAD_GRAYSCALE);
  brick(cv::Rect(0, 0, 384, 384)).copyTo(changed(cv::Rect(576, 576, 384, 384)));
  const std::string floor = (server.dir() / "changed_floor.png").string();
  const std::string run = (server.dir() / "run").string();
  if (!cv::imwrite(floor, changed)) return "";
  const auto sim = testing::RunFleetctl("sim --image " + floor +
                                        " --resolution 0.0005 --frames 80 --seed 5 --out " + run);
  return sim.exit_code == 0 ? run : "";
}

runtime::ChildProcess StartAgent(testing::MapServerFixture& server, const std::string& run,
                                 const std::string& outbox, const std::string& log) {
  return testing::StartDaemon("tracker_agent",
                              {"--run", run, "--domain", std::to_string(kDomain), "--vehicle-id",
                               "agv-5", "--outbox", outbox},
                              (server.dir() / log).string());
}

TEST(AgentPatchFault, PatchesOfChangedFloorSurviveAMapServerOutage) {
  testing::MapServerFixture server("agent_patch_fault", RockFloor(), kDomain);
  const std::string run = ChangedFloorRun(server);
  ASSERT_FALSE(run.empty());
  const std::string outbox = (server.dir() / "outbox.db").string();
  runtime::ChildProcess agent = StartAgent(server, run, outbox, "agent.log");
  auto pose_topic = transport::Topic<fleetloc_VehiclePose>::Create(server.participant(),
                                                                   transport::topics::kVehiclePose);
  auto poses = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      server.participant(), *pose_topic, transport::Qos().Reliable().KeepAll());
  auto health_topic = transport::Topic<fleetloc_VehicleHealth>::Create(
      server.participant(), transport::topics::kVehicleHealth);
  auto health = transport::VehicleStreamReader<fleetloc_VehicleHealth>::Create(
      server.participant(), *health_topic, transport::Qos().Reliable().KeepAll());
  int tracked_while_down = 0;
  std::optional<bool> reachable;  // as the newest health report says
  bool named_unreachable = false;
  auto take_poses = [&](bool down) {
    (void)poses->TakeAll([&](const fleetloc_VehiclePose& p, const dds_sample_info_t&) {
      if (down && p.lock_state == fleetloc_LOCK_TRACKING) ++tracked_while_down;
    });
    (void)health->TakeAll([&](const fleetloc_VehicleHealth& h, const dds_sample_info_t&) {
      reachable = h.map_server_reachable;
      for (uint32_t i = 0; i < h.issues._length; ++i) {
        named_unreachable |=
            transport::GetBounded(h.issues._buffer[i].name) == "map_server_unreachable";
      }
    });
  };
  std::this_thread::sleep_for(std::chrono::seconds(4));
  take_poses(false);
  EXPECT_EQ(reachable, std::optional<bool>(true));
  EXPECT_FALSE(named_unreachable);
  EXPECT_EQ(server.StopServer(SIGKILL), 128 + SIGKILL);
  // Down for longer than the agent's map_server_timeout_s (3 s) plus a health period.
  const auto down_until = std::chrono::steady_clock::now() + std::chrono::seconds(6);
  while (std::chrono::steady_clock::now() < down_until) {
    take_poses(true);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(reachable, std::optional<bool>(false)) << "health while the server is down";
  if (::testing::Test::HasFailure()) {
    std::ifstream log(server.dir() / "agent.log");
    std::cerr << log.rdbuf();
  }
  EXPECT_TRUE(named_unreachable);
  server.StartServer();
  EXPECT_TRUE(Eventually(
      [&] {
        take_poses(false);
        return reachable == true;
      },
      8))
      << "health once the server is back";
  ASSERT_TRUE(Eventually([&] { return !agent.Running(); }, 90));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  // The agent went on tracking from its cache while the server was down. (Its poses reach this
  // participant directly, without the server.)
  EXPECT_GT(tracked_while_down, 50);
  const long long queued =
      testing::SqliteValue(outbox, "SELECT value - 1 FROM meta WHERE name = 'next_sequence'");
  EXPECT_GE(queued, 2) << "the changed floor should have produced patches";
  EXPECT_EQ(testing::SqliteValue(outbox, "SELECT COUNT(*) FROM outbox"), 0)
      << "unacknowledged patches left";
  auto store = mosaic::PatchStore::Open(server.mosaic_path());
  ASSERT_TRUE(store.ok());
  EXPECT_EQ((*store)->Counts(1)->stored, queued) << "every queued patch stored exactly once";
}

// The agent killed (SIGKILL) while its patches wait for a map server that is down: the patches
// stay in its outbox on disk; restarted with the same outbox once the server is back, it sends
// them, and every patch it ever queued is stored exactly once.
TEST(AgentPatchFault, AKilledAgentsQueuedPatchesSurviveItsRestart) {
  testing::MapServerFixture server("agent_restart_fault", RockFloor(), kDomain);
  const std::string run = ChangedFloorRun(server);
  ASSERT_FALSE(run.empty());
  const std::string outbox = (server.dir() / "outbox.db").string();
  runtime::ChildProcess agent = StartAgent(server, run, outbox, "agent_1.log");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  EXPECT_EQ(server.StopServer(SIGKILL), 128 + SIGKILL);
  ASSERT_TRUE(Eventually(
      [&] { return testing::SqliteValue(outbox, "SELECT COUNT(*) FROM outbox") >= 1; }, 30))
      << "no patch queued while the server was down";
  EXPECT_EQ(agent.Stop(SIGKILL), 128 + SIGKILL);
  const long long pending = testing::SqliteValue(outbox, "SELECT COUNT(*) FROM outbox");
  EXPECT_GE(pending, 1) << "the queued patches are on disk after the kill";
  server.StartServer();
  runtime::ChildProcess restarted = StartAgent(server, run, outbox, "agent_2.log");
  ASSERT_TRUE(Eventually([&] { return !restarted.Running(); }, 90));
  EXPECT_EQ(restarted.Wait(std::chrono::seconds(1)), 0);
  const long long queued =
      testing::SqliteValue(outbox, "SELECT value - 1 FROM meta WHERE name = 'next_sequence'");
  EXPECT_GE(queued, pending);
  EXPECT_EQ(testing::SqliteValue(outbox, "SELECT COUNT(*) FROM outbox"), 0)
      << "unacknowledged patches left";
  auto store = mosaic::PatchStore::Open(server.mosaic_path());
  ASSERT_TRUE(store.ok());
  EXPECT_EQ((*store)->Counts(1)->stored, queued) << "every queued patch stored exactly once";
}

}  // namespace
}  // namespace fleetloc
