// Scale-out: one mosaic served by two map_server processes, each owning half of the tile columns
// (configured `owned_tiles`), and a tracker_agent replaying a drive that crosses the boundary
// again and again. The vehicle must track every frame within millimetres of truth with its tiles
// coming from the right server (each serves only its half; neither answers for the other's) and
// never wait out a tile timeout at the crossing. `fleetctl remap` follows both servers' jobs. A
// vehicle started while one server is down keeps its patches until that replica is there too.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "map_server_fixture.h"
#include "published_poses.h"
#include "run_io/run.h"
#include "sqlite_value.h"
#include "transport/mosaic_messages.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 102;

// The newest counters of every map server heard from within `wait_s`, by service id.
std::map<std::string, std::map<std::string, uint64_t>> ServerCounters(transport::Participant& p,
                                                                      size_t servers,
                                                                      double wait_s) {
  auto topic =
      transport::Topic<fleetloc_ServiceHealth>::Create(p, transport::topics::kServiceHealth);
  auto reader = transport::Reader<fleetloc_ServiceHealth>::Create(
      p.get(), *topic, transport::PeriodicStateQos(3, 5));
  std::map<std::string, std::map<std::string, uint64_t>> counters;
  Eventually(
      [&] {
        (void)reader->TakeAll([&](const fleetloc_ServiceHealth& h, const dds_sample_info_t&) {
          auto& mine = counters[transport::GetBounded(h.service_id)];
          for (uint32_t i = 0; i < h.counters._length; ++i) {
            mine[transport::GetBounded(h.counters._buffer[i].name)] = h.counters._buffer[i].value;
          }
        });
        return counters.size() >= servers;
      },
      wait_s);
  return counters;
}

class SplitServers {
 public:
  // `start_east` false: only ms-west runs until StartEast().
  explicit SplitServers(const testing::ScratchDir& dir, bool start_east = true) : dir_(dir) {
    const std::string image = dir / "floor.png";
    EXPECT_TRUE(
        cv::imwrite(image, cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/moss_2560x1600.jpg",
                                      cv::IMREAD_GRAYSCALE)));
    mosaic::ImportOptions options;
    options.resolution_m = 0.0005;  // 1.28 m x 0.8 m, 10 x 7 tiles of 256 px
    auto imported = mosaic::ImportImage(image, options, dir / "west.db");
    EXPECT_TRUE(imported.ok()) << imported.status().message();
    if (imported.ok()) layout = *imported;
    // Each server keeps its own replica of the one mosaic (same id and version).
    std::filesystem::copy_file(dir / "west.db", dir / "east.db");
    Start("ms-west", 0, 5);
    if (start_east) StartEast();
  }
  ~SplitServers() {
    for (auto& [id, server] : servers_)
      EXPECT_EQ(server.Stop(SIGTERM), 0) << id << " did not stop cleanly";
  }

  void StartEast() { Start("ms-east", 5, 10); }

  mosaic::MosaicLayout layout;

 private:
  void Start(const std::string& id, int col_begin, int col_end) {
    const nlohmann::json config{
        {"server_id", id},
        {"mosaic", dir_ / (id.substr(3) + ".db")},
        {"domain", kDomain},
        {"owned_tiles",
         {{"col_begin", col_begin}, {"col_end", col_end}, {"row_begin", 0}, {"row_end", 7}}}};
    const std::string path = dir_ / (id + ".json");
    std::ofstream(path) << config.dump(2);
    servers_.emplace(id,
                     testing::StartDaemon("map_server", {"--config", path}, dir_ / (id + ".log")));
  }

  const testing::ScratchDir& dir_;
  std::map<std::string, runtime::ChildProcess> servers_;
};

TEST(MapServerSplit, AVehicleCrossingTheBoundaryTracksOnTilesFromBothServers) {
  testing::ScratchDir dir("map_server_split");
  SplitServers servers(dir);
  const std::string run_dir = dir / "run";
  ASSERT_EQ(testing::RunFleetctl("sim --mosaic " + (dir / "west.db") +
                                 " --frames 60 --seed 3 --out " + run_dir)
                .exit_code,
            0);
  Result<run_io::Run> run = run_io::ReadRun(run_dir);
  ASSERT_TRUE(run.ok()) << run.status().message();
  // The drive crosses the boundary (x = 0.64 m, tile column 5) more than once.
  int crossings = 0;
  for (size_t i = 1; i < run->truth.size(); ++i) {
    crossings += (run->truth[i - 1].pose.x < 0.64) != (run->truth[i].pose.x < 0.64);
  }
  ASSERT_GE(crossings, 2);

  auto p = transport::Participant::Create(kDomain);
  ASSERT_TRUE(p.ok()) << p.status().message();
  auto pose_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(*p, transport::topics::kVehiclePose);
  auto pose_reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      *p, *pose_topic, transport::Qos().Reliable().KeepAll());
  ASSERT_EQ(ServerCounters(*p, 2, 20).size(), 2u) << "both map servers report health";

  const std::string summary_path = dir / "summary.json";
  runtime::ChildProcess agent =
      testing::StartDaemon("tracker_agent",
                           {"--run", run_dir, "--domain", std::to_string(kDomain), "--vehicle-id",
                            "agv-7", "--outbox", dir / "outbox.db", "--summary", summary_path},
                           dir / "agent.log");
  std::vector<transport::PoseReport> published;
  ASSERT_TRUE(Eventually(
      [&] {
        testing::TakePoses(*pose_reader, &published);
        return !agent.Running();
      },
      90));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  testing::TakePoses(*pose_reader, &published);

  int frames = 0, tracking = 0;
  for (const geometry::StampedPose& truth : run->truth) {
    const transport::PoseReport* pose = testing::PoseAt(published, truth.t);
    if (pose == nullptr) continue;  // the first frames may go out before our reader matched
    ++frames;
    if (pose->state != tracking::LockState::kTracking) continue;
    ++tracking;
    EXPECT_LT(std::hypot(pose->base_in_map.pose.x - truth.pose.x,
                         pose->base_in_map.pose.y - truth.pose.y),
              0.002)
        << "at t=" << truth.t;
  }
  EXPECT_GT(frames, 50);
  EXPECT_EQ(tracking, frames) << "every frame tracks, across the boundary too";

  std::ifstream in(summary_path);
  ASSERT_TRUE(in.good()) << "no summary";
  const nlohmann::json tiles = nlohmann::json::parse(in)["tiles"];
  EXPECT_EQ(tiles.value("timeouts", -1), 0) << tiles.dump();
  EXPECT_EQ(tiles.value("errors", -1), 0) << tiles.dump();
  EXPECT_EQ(tiles.value("requested", 0), tiles.value("received", -1))
      << "every tile asked for came, once";

  // Each server served its own half and passed over the other's.
  auto counters = ServerCounters(*p, 2, 5);
  for (const char* id : {"ms-west", "ms-east"}) {
    EXPECT_GT(counters[id]["tiles_served"], 0u) << id;
    EXPECT_GT(counters[id]["tiles_not_owned"], 0u) << id;
  }
}

TEST(MapServerSplit, FleetctlRemapWaitsForEveryServerAndReportsEach) {
  testing::ScratchDir dir("map_server_split_remap");
  SplitServers servers(dir);
  const std::string remap = "remap --domain " + std::to_string(kDomain) + " --timeout 60 --region ";
  const testing::CommandResult done = testing::RunFleetctl(remap + "0.1,0.1,1.2,0.7");
  ASSERT_EQ(done.exit_code, 0) << done.err;
  const nlohmann::json outcome = nlohmann::json::parse(done.out);
  ASSERT_EQ(outcome["servers"].size(), 2u) << done.out;
  EXPECT_EQ(outcome["servers"][0]["server_id"], "ms-east");
  EXPECT_EQ(outcome["servers"][1]["server_id"], "ms-west");
  for (const nlohmann::json& server : outcome["servers"])
    EXPECT_EQ(server["state"], "done") << done.out;
  EXPECT_EQ(outcome["state"], "done");
  // A region off the mosaic: both refuse it, and fleetctl says so with a non-zero exit.
  const testing::CommandResult off = testing::RunFleetctl(remap + "5,5,6,6");
  EXPECT_NE(off.exit_code, 0);
  const nlohmann::json refused = nlohmann::json::parse(off.out);
  ASSERT_EQ(refused["servers"].size(), 2u) << off.out;
  for (const nlohmann::json& server : refused["servers"])
    EXPECT_EQ(server["state"], "rejected") << off.out;
  EXPECT_NE(off.err.find("outside the mosaic"), std::string::npos) << off.err;
}

// A third "server" announcing the mosaic that reads remap commands but never answers (hung): the
// command is expected from it, and at the time-out fleetctl prints the two outcomes it has, names
// the silent one under "missing" and exits non-zero.
TEST(MapServerSplit, FleetctlRemapNamesAServerThatNeverAnswered) {
  testing::ScratchDir dir("map_server_split_mute");
  SplitServers servers(dir);
  auto p = transport::Participant::Create(kDomain);
  ASSERT_TRUE(p.ok()) << p.status().message();
  auto info_topic =
      transport::Topic<fleetloc_MosaicInfo>::Create(*p, transport::topics::kMosaicInfo);
  auto command_topic =
      transport::Topic<fleetloc_RemapCommand>::Create(*p, transport::topics::kRemapCommand);
  ASSERT_TRUE(info_topic.ok() && command_topic.ok());
  auto announce = transport::Writer<fleetloc_MosaicInfo>::Create(p->get(), *info_topic,
                                                                 transport::DurableStateQos());
  auto commands = transport::Reader<fleetloc_RemapCommand>::Create(p->get(), *command_topic,
                                                                   transport::CommandQos());
  ASSERT_TRUE(announce.ok() && commands.ok());
  ASSERT_TRUE(
      announce->Write(transport::ToIdl(servers.layout, "ms-mute", mosaic::TileOwnership{})).ok());

  const testing::CommandResult r = testing::RunFleetctl(
      "remap --domain " + std::to_string(kDomain) + " --timeout 8 --region 0.1,0.1,1.2,0.7");
  EXPECT_NE(r.exit_code, 0);
  const nlohmann::json outcome = nlohmann::json::parse(r.out, nullptr, false);
  ASSERT_TRUE(outcome.is_object()) << r.out << r.err;
  EXPECT_EQ(outcome["missing"], nlohmann::json::array({"ms-mute"})) << r.out;
  ASSERT_EQ(outcome["servers"].size(), 2u) << r.out;
  for (const nlohmann::json& server : outcome["servers"]) EXPECT_EQ(server["state"], "done");
  EXPECT_NE(r.err.find("ms-mute"), std::string::npos) << r.err;
}

// Started while ms-east is down, a vehicle knows only ms-west: it must not let ms-west's
// acknowledgement alone take a patch out of its outbox (ms-east's replica would never get it).
// Its patches wait until the servers announced cover the mosaic; once ms-east is up, both
// replicas store every patch that left the outbox.
TEST(MapServerSplit, PatchesWaitForAServerThatWasDownAtTheVehiclesStart) {
  testing::ScratchDir dir("map_server_split_late");
  SplitServers servers(dir, /*start_east=*/false);
  // The vehicle drives over the floor with a new brick marking across the boundary.
  cv::Mat floor = cv::imread(dir / "floor.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat brick =
      cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/brick.png", cv::IMREAD_GRAYSCALE);
  brick(cv::Rect(0, 0, 256, 256)).copyTo(floor(cv::Rect(1152, 672, 256, 256)));
  ASSERT_TRUE(cv::imwrite(dir / "changed_floor.png", floor));
  const nlohmann::json config{{"vehicle_id", "agv-9"},
                              {"domain", kDomain},
                              {"source", "sim"},
                              {"sim_floor", dir / "changed_floor.png"},
                              {"mosaic_wait_s", 3}};
  std::ofstream(dir / "agv-9.json") << config.dump(2);
  const std::string outbox = dir / "outbox.db";
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent", {"--config", dir / "agv-9.json", "--outbox", outbox}, dir / "agent.log");

  ASSERT_TRUE(Eventually([&] { return testing::QueuedPatches(outbox) >= 2; }, 90))
      << "no patch queued";
  std::this_thread::sleep_for(std::chrono::seconds(2));  // time to send them, were it allowed
  EXPECT_EQ(testing::SqliteValue(dir / "west.db", "SELECT COUNT(*) FROM patches"), 0)
      << "patches went out while a replica was unknown";

  servers.StartEast();
  const long long queued = testing::QueuedPatches(outbox);
  EXPECT_TRUE(Eventually(
      [&] {
        return testing::SqliteValue(dir / "west.db", "SELECT COUNT(*) FROM patches") >= queued &&
               testing::SqliteValue(dir / "east.db", "SELECT COUNT(*) FROM patches") >= queued;
      },
      60))
      << "the queued patches did not reach both replicas";
  EXPECT_EQ(agent.Stop(SIGTERM, std::chrono::seconds(30)), 0);
  for (const char* replica : {"west.db", "east.db"}) {
    EXPECT_EQ(testing::AcknowledgedButMissing(outbox, "agv-9", dir / replica), 0) << replica;
  }
}

}  // namespace
}  // namespace fleetloc
