// Faults of the map server: killed with SIGKILL in the middle of a re-mapping job, it leaves the
// previous mosaic version whole (every tile byte-identical, patches unfolded); restarted, it serves
// that version and the same job runs to completion. Killed while a vehicle asks for tiles, the
// requests it missed are asked again once it is back, without waiting out a timeout per tile.
#include <gtest/gtest.h>

#include <csignal>
#include <nlohmann/json.hpp>

#include "changed_floor_patches.h"
#include "map_server_fixture.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_codec.h"
#include "mosaic/tile_store.h"
#include "transport/dds_tile_loader.h"
#include "transport/patch_client.h"
#include "transport/tile_client.h"

namespace fleetloc {
namespace {

using testing::Eventually;
using testing::Scene;
constexpr uint32_t kDomain = 83;

// Every tile of every level, as stored bytes.
std::map<mosaic::TileKey, std::vector<std::uint8_t>> AllTiles(const std::string& path) {
  auto store = mosaic::TileStore::Open(path, mosaic::OpenMode::kReadOnly);
  EXPECT_TRUE(store.ok());
  std::map<mosaic::TileKey, std::vector<std::uint8_t>> tiles;
  const mosaic::MosaicLayout layout = (*store)->layout();
  for (int level = 0; level < layout.levels; ++level) {
    mosaic::TilesCovering(layout, level,
                          {0, 0, layout.LevelWidth(level), layout.LevelHeight(level)})
        .ForEach([&](const mosaic::TileKey& k) { tiles[k] = *(*store)->ReadTileBytes(k); });
  }
  return tiles;
}

TEST(MapServerFault, KilledDuringARemapJobKeepsThePreviousVersionAndTheJobReruns) {
  Scene scene;
  // The test sends its 64 patches once, at once: no rate limit and room for all in the decoding
  // queue (a vehicle would send the ones not acknowledged again later).
  testing::MapServerFixture server(
      "map_server_fault", scene.old_floor, kDomain, 0.0005, 256,
      R"("patch_intake": {"patches_per_s": 1000, "burst": 1000, "queue": 128})");
  auto patches = transport::PatchClient::Create(server.participant(), "agv-9");
  ASSERT_TRUE(patches.ok());
  ASSERT_TRUE(Eventually([&] { return (*patches)->ServerMatched(); }));
  // Enough patches over the whole floor that the job runs for a while.
  int sent = 0;
  for (int y = 200; y <= 820; y += 90) {
    for (int x = 200; x <= 820; x += 90) {
      const uint64_t sequence = static_cast<uint64_t>(++sent);
      ASSERT_TRUE(testing::SendPatch(
          **patches,
          testing::ScenePatch(scene, sequence, {x, y}, {Scene::kRes, -Scene::kRes, 0.002})));
    }
  }
  size_t acked = 0;
  ASSERT_TRUE(Eventually(
      [&] {
        auto acks = (*patches)->TakeAcks();
        acked += acks.ok() ? acks->size() : 0;
        return acked == static_cast<size_t>(sent);
      },
      60));
  const auto before = AllTiles(server.mosaic_path());
  // Start the job and kill the server once it reports progress.
  auto status_topic = transport::Topic<fleetloc_RemapStatus>::Create(
      server.participant(), transport::topics::kRemapStatus);
  auto statuses = transport::Reader<fleetloc_RemapStatus>::Create(
      server.participant().get(), *status_topic, transport::DurableStateQos());
  const std::string whole = "0,0,0.512,0.512";
  const std::string fleetctl = std::string(FLEETLOC_BINARY_DIR) + "/bin/fleetctl";
  auto remap = runtime::ChildProcess::Start(
      fleetctl,
      {"remap", "--domain", std::to_string(kDomain), "--region", whole, "--timeout", "60"},
      (server.dir() / "remap_1.log").string());
  ASSERT_TRUE(remap.ok());
  bool running = false;
  ASSERT_TRUE(Eventually(
      [&] {
        (void)statuses->TakeAll([&](const fleetloc_RemapStatus& s, const dds_sample_info_t&) {
          running = running || (s.state == fleetloc_REMAP_RUNNING && s.progress > 0.1f);
        });
        return running;
      },
      60));
  EXPECT_EQ(server.StopServer(SIGKILL), 128 + SIGKILL);
  remap->Stop(SIGTERM);
  // The previous version is whole and no patch counts as folded.
  EXPECT_EQ(AllTiles(server.mosaic_path()), before);
  auto store = mosaic::TileStore::Open(server.mosaic_path(), mosaic::OpenMode::kReadOnly);
  EXPECT_EQ((*store)->version(), 1);
  EXPECT_EQ((*mosaic::PatchStore::Open(server.mosaic_path()))->Counts(1)->folded, 0);
  // Restarted, the server runs the same job to completion.
  server.StartServer();
  const testing::CommandResult rerun = testing::RunFleetctl(
      "remap --domain " + std::to_string(kDomain) + " --region " + whole + " --timeout 120");
  ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
  const auto outcome = nlohmann::json::parse(rerun.out);
  EXPECT_EQ(outcome["new_version"], 2);
  EXPECT_EQ(outcome["patches_folded"], sent);
}

TEST(MapServerFault, KilledInsideTheTileCommitKeepsServingThePreviousVersion) {
  Scene scene;
  // The server pauses 30 s after writing the first tile of the new version, not yet committed.
  ::setenv("FLEETLOC_FAILPOINT_COMMIT_PAUSE_S", "30", 1);
  testing::MapServerFixture server("map_server_fault_commit", scene.old_floor, kDomain);
  ::unsetenv("FLEETLOC_FAILPOINT_COMMIT_PAUSE_S");
  auto patches = transport::PatchClient::Create(server.participant(), "agv-9");
  ASSERT_TRUE(patches.ok());
  ASSERT_TRUE(Eventually([&] { return (*patches)->ServerMatched(); }));
  ASSERT_TRUE(testing::SendPatch(**patches, testing::ScenePatch(scene, 1, {490, 425}, {})));
  ASSERT_TRUE(testing::SendPatch(**patches, testing::ScenePatch(scene, 2, {470, 440}, {})));
  ASSERT_TRUE(Eventually([&] { return server.HealthCounter("patches_stored") == 2; }));
  const auto before = AllTiles(server.mosaic_path());
  auto status_topic = transport::Topic<fleetloc_RemapStatus>::Create(
      server.participant(), transport::topics::kRemapStatus);
  auto statuses = transport::Reader<fleetloc_RemapStatus>::Create(
      server.participant().get(), *status_topic, transport::DurableStateQos());
  const std::string region = testing::RegionAroundChange(scene);
  auto remap =
      runtime::ChildProcess::Start(std::string(FLEETLOC_BINARY_DIR) + "/bin/fleetctl",
                                   {"remap", "--domain", std::to_string(kDomain), "--region",
                                    region, "--mode", "replace", "--timeout", "60"},
                                   (server.dir() / "remap_commit.log").string());
  ASSERT_TRUE(remap.ok());
  // Killed once it says it is writing the new version's tiles (and has not committed them).
  bool committing = false;
  ASSERT_TRUE(Eventually(
      [&] {
        (void)statuses->TakeAll([&](const fleetloc_RemapStatus& s, const dds_sample_info_t&) {
          committing = committing || (s.state == fleetloc_REMAP_RUNNING &&
                                      transport::GetBounded(s.phase) == "commit" &&
                                      s.progress > 0 && s.progress < 1);
        });
        return committing;
      },
      60));
  EXPECT_EQ(server.StopServer(SIGKILL), 128 + SIGKILL);
  remap->Stop(SIGTERM);
  // The file holds the previous version whole; the patches' folded marks do not count.
  EXPECT_EQ(AllTiles(server.mosaic_path()), before);
  EXPECT_EQ(
      (*mosaic::TileStore::Open(server.mosaic_path(), mosaic::OpenMode::kReadOnly))->version(), 1);
  EXPECT_EQ((*mosaic::PatchStore::Open(server.mosaic_path()))->Counts(1)->folded, 0);
  // Restarted (no pause now), it serves the previous version's tiles, then re-maps them.
  server.StartServer();
  auto client = transport::TileClient::Create(server.participant(), "agv-8");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(Eventually([&] { return (*client)->RequestsMatched(); }));
  // Asked again until answered: the dead server's reader stays matched until its lease ends, so a
  // request may reach only it.
  std::vector<transport::ReceivedTile> tiles;
  uint32_t request = 0;
  ASSERT_TRUE(Eventually([&] {
    EXPECT_TRUE((*client)->Request(++request, "", {{0, 1, 1}}).ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    auto taken = (*client)->TakeTiles();
    for (auto& t : taken.ok() ? *taken : std::vector<transport::ReceivedTile>{})
      tiles.push_back(std::move(t));
    return !tiles.empty();
  }));
  EXPECT_EQ(tiles[0].version, 1);
  EXPECT_EQ(tiles[0].data, before.at({0, 1, 1}));
  const testing::CommandResult rerun =
      testing::RunFleetctl("remap --domain " + std::to_string(kDomain) + " --region " + region +
                           " --mode replace --timeout 120");
  ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
  EXPECT_EQ(nlohmann::json::parse(rerun.out)["new_version"], 2);
}

TEST(MapServerFault, TilesAskedForWhileTheServerWasDownAreAskedAgainWhenItReturns) {
  Scene scene;
  testing::MapServerFixture server("map_server_fault_tiles", scene.old_floor, kDomain);
  auto client = transport::TileClient::Create(server.participant(), "agv-8");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(Eventually([&] { return (*client)->RequestsMatched(); }));
  const mosaic::MosaicLayout layout = server.layout();
  const auto timeout = std::chrono::seconds(4);
  transport::DdsTileLoader loader(client->get(), layout.mosaic_id, layout.tile_size_px, timeout);
  ASSERT_TRUE(loader.Load({0, 0, 0}).ok());
  EXPECT_EQ(server.StopServer(SIGKILL), 128 + SIGKILL);
  // Asked for while nobody serves: these requests are lost with the dead server.
  const std::vector<mosaic::TileKey> ahead = {{0, 1, 0}, {0, 0, 1}, {0, 1, 1}};
  ASSERT_TRUE(loader.Prefetch(ahead).ok());
  server.StartServer();
  EXPECT_EQ(server.HealthCounter("rejected_tile_request"), 0u);  // the new server reports
  std::this_thread::sleep_for(timeout / 2);  // so the prefetched requests count as lost
  for (const mosaic::TileKey& key : ahead) {
    Result<cv::Mat> tile = loader.Load(key);
    ASSERT_TRUE(tile.ok()) << mosaic::ToString(key) << ": " << tile.status().message();
    EXPECT_EQ(tile->cols, layout.tile_size_px);
  }
  EXPECT_EQ(loader.stats().timeouts, 0);
  EXPECT_GE(loader.stats().reasked, static_cast<long long>(ahead.size()));
}

// A map server killed while a vehicle waits for one of its tiles: the wait ends once the tile's
// server is known unreachable (here: 300 ms after the kill, as the agent's MapServerDirectory would
// say after its health timeout), not after the whole tile timeout. Before, a frame that needed ten
// tiles of a dead server stalled ten timeouts (20 s) before the agent could say so.
TEST(MapServerFault, AWaitForATileEndsOnceItsServerIsKnownUnreachable) {
  Scene scene;
  testing::MapServerFixture server("map_server_fault_wait", scene.old_floor, kDomain);
  auto client = transport::TileClient::Create(server.participant(), "agv-9");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(Eventually([&] { return (*client)->RequestsMatched(); }));
  const mosaic::MosaicLayout layout = server.layout();
  transport::DdsTileLoader loader(client->get(), layout.mosaic_id, layout.tile_size_px,
                                  std::chrono::seconds(30));
  ASSERT_TRUE(loader.Load({0, 0, 0}).ok());
  EXPECT_EQ(server.StopServer(SIGKILL), 128 + SIGKILL);
  const auto silent_from = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
  loader.SetReachability(
      [&](const mosaic::TileKey&) { return std::chrono::steady_clock::now() < silent_from; });
  const Result<cv::Mat> tile = loader.Load({0, 1, 1});
  ASSERT_FALSE(tile.ok());
  EXPECT_NE(tile.status().message().find("unreachable"), std::string::npos)
      << tile.status().message();
  EXPECT_EQ(loader.stats().unserved, 1);
  EXPECT_EQ(loader.stats().timeouts, 0);
}

}  // namespace
}  // namespace fleetloc
