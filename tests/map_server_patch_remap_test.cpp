// Patches and re-mapping through DDS against a map_server process: patches are stored once and
// acknowledged, bad ones are rejected with a reason and counted, and `fleetctl remap` folds them
// into a new mosaic version that vehicles are told about (TileUpdate, MosaicInfo) and can fetch.
// A forged vehicle's patches change nothing, the re-map reports them per vehicle, and the vehicle
// is quarantined (alerted in health, refused on arrival) until a maintainer releases it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "changed_floor_patches.h"
#include "map_server_fixture.h"
#include "mapping/forged_patches.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_codec.h"
#include "mosaic/tile_store.h"
#include "transport/mosaic_messages.h"
#include "transport/patch_client.h"
#include "transport/remap_client.h"
#include "transport/tile_client.h"

namespace fleetloc {
namespace {

using testing::Eventually;
using testing::Scene;
constexpr uint32_t kDomain = 82;

class MapServerPatchRemap : public ::testing::Test {
 protected:
  MapServerPatchRemap() : server_("map_server_patch_remap", scene_.old_floor, kDomain) {
    auto client = transport::PatchClient::Create(server_.participant(), "agv-1");
    EXPECT_TRUE(client.ok()) << client.status().message();
    patches_ = std::move(client).value();
    EXPECT_TRUE(Eventually([&] { return patches_->ServerMatched(); }));
  }

  transport::PatchToSend PatchAt(uint64_t sequence, cv::Point centre,
                                 const geometry::Pose2& error) {
    return testing::ScenePatch(scene_, sequence, centre, error, server_.layout().mosaic_id);
  }

  // Waits until acks for `count` sequence numbers arrived; returns them by sequence.
  std::map<uint64_t, transport::ReceivedAck> Acks(size_t count) {
    std::map<uint64_t, transport::ReceivedAck> acks;
    Eventually([&] {
      auto taken = patches_->TakeAcks();
      EXPECT_TRUE(taken.ok());
      for (auto& a : *taken) acks[a.sequence] = a;
      return acks.size() >= count;
    });
    return acks;
  }

  void SendTheTwoPatches() {
    ASSERT_TRUE(testing::SendPatch(
        *patches_, PatchAt(1, {490, 425}, {2 * Scene::kRes, -1.5 * Scene::kRes, 0.005})));
    ASSERT_TRUE(testing::SendPatch(
        *patches_, PatchAt(2, {470, 440}, {-Scene::kRes, 2.5 * Scene::kRes, -0.003})));
    const auto acks = Acks(2);
    ASSERT_EQ(acks.size(), 2u);
    for (const auto& [seq, ack] : acks) {
      EXPECT_EQ(ack.status, fleetloc_PATCH_STORED) << ack.reason;
      EXPECT_EQ(ack.server_id, "map-t");  // the ack writer names its server (USER_DATA)
    }
  }

  // `fleetctl remap` on this domain over the region around the change.
  testing::CommandResult Remap(const std::string& region, const std::string& extra = "") {
    return testing::RunFleetctl("remap --domain " + std::to_string(kDomain) + " --region " +
                                region + " --mode replace --timeout 120 " + extra);
  }
  std::string RegionAroundChange() const { return testing::RegionAroundChange(scene_); }

  // Fetches tile (0, 1, 1), expects it at `version`, and returns the mean absolute difference of
  // its part of the changed area from `floor` (255 when no tile came).
  double ChangedPartDifference(transport::TileClient& client, uint64_t request, long long version,
                               const cv::Mat& floor) {
    EXPECT_TRUE(Eventually([&] { return client.RequestsMatched(); }));
    EXPECT_TRUE(client.Request(request, "", {{0, 1, 1}}).ok());
    std::vector<transport::ReceivedTile> tiles;
    const bool came = Eventually([&] {
      auto taken = client.TakeTiles();
      EXPECT_TRUE(taken.ok());
      for (auto& t : *taken) tiles.push_back(std::move(t));
      return !tiles.empty();
    });
    if (!came) return 255.0;
    EXPECT_EQ(tiles[0].version, version);
    const cv::Mat tile = *mosaic::DecodeTile(tiles[0].data, 256);
    const cv::Rect part = scene_.change & cv::Rect(256, 256, 256, 256);
    cv::Mat diff;
    cv::absdiff(tile(part - cv::Point(256, 256)), floor(part), diff);
    return cv::mean(diff)[0];
  }

  Scene scene_;
  testing::MapServerFixture server_;
  std::unique_ptr<transport::PatchClient> patches_;
};

TEST_F(MapServerPatchRemap, PatchesAreStoredOnceAndAcknowledged) {
  SendTheTwoPatches();
  ASSERT_TRUE(testing::SendPatch(*patches_, PatchAt(1, {490, 425}, {})));  // a retry of patch 1
  const auto acks = Acks(1);
  ASSERT_EQ(acks.count(1), 1u);
  EXPECT_EQ(acks.at(1).status, fleetloc_PATCH_DUPLICATE);
  auto store = mosaic::PatchStore::Open(server_.mosaic_path());
  ASSERT_TRUE(store.ok());
  EXPECT_EQ((*store)->Counts(1)->stored, 2);
  EXPECT_EQ(server_.HealthCounter("patches_duplicate"), 1u);
}

TEST_F(MapServerPatchRemap, BadPatchesAreRejectedWithAReasonAndCounted) {
  transport::PatchToSend oversized = PatchAt(10, {490, 425}, {});
  oversized.png.resize(4300000, 7);  // more than max_patch_bytes (4 MiB): a large DDS sample too
  transport::PatchToSend corrupt = PatchAt(11, {490, 425}, {});
  corrupt.png.resize(40);  // a PNG header and nothing after it
  transport::PatchToSend foreign = PatchAt(12, {490, 425}, {});
  foreign.mosaic_id = "0123456789abcdef0123456789abcdef";
  transport::PatchToSend nan_pose = PatchAt(13, {490, 425}, {});
  nan_pose.pose.x = std::nan("");
  transport::PatchToSend wrong_scale = PatchAt(14, {490, 425}, {});
  wrong_scale.resolution_m = 0.001;
  transport::PatchToSend zero_covariance = PatchAt(15, {490, 425}, {});
  std::fill(std::begin(zero_covariance.covariance), std::end(zero_covariance.covariance), 0.0);
  transport::PatchToSend negative_covariance = PatchAt(16, {490, 425}, {});
  for (double& c : negative_covariance.covariance) c = -c;
  for (const auto* p : {&oversized, &corrupt, &foreign, &nan_pose, &wrong_scale, &zero_covariance,
                        &negative_covariance}) {
    ASSERT_TRUE(testing::SendPatch(*patches_, *p));
  }
  const auto acks = Acks(7);
  ASSERT_EQ(acks.size(), 7u);
  for (const auto& [seq, ack] : acks) {
    EXPECT_EQ(ack.status, fleetloc_PATCH_REJECTED) << seq;
    EXPECT_FALSE(ack.reason.empty()) << seq;
  }
  EXPECT_NE(acks.at(10).reason.find("bytes"), std::string::npos) << acks.at(10).reason;
  EXPECT_NE(acks.at(12).reason.find("unknown mosaic"), std::string::npos) << acks.at(12).reason;
  EXPECT_EQ(server_.HealthCounter("rejected_patch_oversized"), 1u);
  EXPECT_EQ(server_.HealthCounter("rejected_patch_image"), 1u);
  EXPECT_EQ(server_.HealthCounter("rejected_patch_mosaic"), 1u);
  EXPECT_EQ(server_.HealthCounter("rejected_patch_malformed"), 2u);
  EXPECT_EQ(server_.HealthCounter("rejected_patch_covariance"), 2u);
  EXPECT_NE(acks.at(15).reason.find("positive definite"), std::string::npos) << acks.at(15).reason;
  // Nothing of them was stored, and the server still takes good patches.
  SendTheTwoPatches();
  EXPECT_EQ((*mosaic::PatchStore::Open(server_.mosaic_path()))->Counts(1)->stored, 2);
}

TEST_F(MapServerPatchRemap, RemapFoldsThePatchesAndAnnouncesTheNewVersion) {
  SendTheTwoPatches();
  auto client = transport::TileClient::Create(server_.participant(), "agv-2");
  ASSERT_TRUE(client.ok());
  auto update_topic = transport::Topic<fleetloc_TileUpdate>::Create(server_.participant(),
                                                                    transport::topics::kTileUpdate);
  auto updates = transport::Reader<fleetloc_TileUpdate>::Create(
      server_.participant().get(), *update_topic, transport::DurableStateQos(32));
  // A preview on the server's file first: the same tiles and verdicts, nothing written.
  const testing::CommandResult preview =
      testing::RunFleetctl("remap --dry-run --mosaic " + server_.mosaic_path() + " --region " +
                           RegionAroundChange() + " --mode replace");
  ASSERT_EQ(preview.exit_code, 0) << preview.err;
  const auto previewed = nlohmann::json::parse(preview.out);
  EXPECT_EQ(previewed["state"], "preview");
  EXPECT_EQ(previewed["version"], 1);
  EXPECT_EQ(previewed["patches_folded"], 2);
  EXPECT_NE(std::find(previewed["tiles"].begin(), previewed["tiles"].end(), "L0/C1/R1"),
            previewed["tiles"].end())
      << preview.out;
  const testing::CommandResult no_file =
      testing::RunFleetctl("remap --dry-run --region " + RegionAroundChange());
  EXPECT_NE(no_file.exit_code, 0);
  EXPECT_NE(no_file.err.find("--dry-run needs --mosaic"), std::string::npos) << no_file.err;
  const testing::CommandResult remap = Remap(RegionAroundChange());
  ASSERT_EQ(remap.exit_code, 0) << remap.err;
  const auto outcome = nlohmann::json::parse(remap.out);
  EXPECT_EQ(outcome["state"], "done");
  EXPECT_EQ(outcome["new_version"], 2);
  EXPECT_EQ(outcome["patches_folded"], 2);
  EXPECT_EQ(outcome["tiles_changed"], previewed["tiles_changed"]);
  std::vector<mosaic::TileKey> changed;
  ASSERT_TRUE(Eventually([&] {
    (void)updates->TakeAll([&](const fleetloc_TileUpdate& u, const dds_sample_info_t&) {
      EXPECT_EQ(u.version, 2);
      for (uint32_t i = 0; i < u.tiles._length; ++i)
        changed.push_back(transport::FromIdl(u.tiles._buffer[i]));
    });
    return !changed.empty();
  }));
  EXPECT_NE(std::find(changed.begin(), changed.end(), mosaic::TileKey{0, 1, 1}), changed.end());
  ASSERT_TRUE(Eventually([&] {
    auto info = (*client)->LatestMosaicInfo();
    return info && info->version == 2;
  }));
  // A vehicle fetching tile (0, 1, 1) now gets the changed floor.
  EXPECT_LT(ChangedPartDifference(**client, 5, 2, scene_.new_floor), 3.0);
}

// After a re-map, `fleetctl mosaic rollback` run beside the running server (a dry run first,
// which changes nothing) writes version 3 with version 1's tiles; the server serves and announces
// it within moments, and a vehicle fetching the changed tile gets the old floor back.
TEST_F(MapServerPatchRemap, ARollbackBesideTheRunningServerIsAnnouncedAndServed) {
  SendTheTwoPatches();
  ASSERT_EQ(Remap(RegionAroundChange()).exit_code, 0);
  auto client = transport::TileClient::Create(server_.participant(), "agv-2");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(Eventually([&] {
    auto info = (*client)->LatestMosaicInfo();
    return info && info->version == 2;
  }));
  auto update_topic = transport::Topic<fleetloc_TileUpdate>::Create(server_.participant(),
                                                                    transport::topics::kTileUpdate);
  auto updates = transport::Reader<fleetloc_TileUpdate>::Create(
      server_.participant().get(), *update_topic, transport::DurableStateQos(32));
  const std::string rollback = "mosaic rollback " + server_.mosaic_path() + " --to-version 1";
  const testing::CommandResult dry = testing::RunFleetctl(rollback + " --dry-run");
  ASSERT_EQ(dry.exit_code, 0) << dry.err;
  EXPECT_EQ(nlohmann::json::parse(dry.out)["new_version"], 2);
  const testing::CommandResult done = testing::RunFleetctl(rollback);
  ASSERT_EQ(done.exit_code, 0) << done.err;
  const auto outcome = nlohmann::json::parse(done.out);
  EXPECT_EQ(outcome["new_version"], 3);
  EXPECT_EQ(outcome["tiles"], nlohmann::json::parse(dry.out)["tiles"]);
  std::vector<mosaic::TileKey> changed;
  ASSERT_TRUE(Eventually([&] {
    (void)updates->TakeAll([&](const fleetloc_TileUpdate& u, const dds_sample_info_t&) {
      if (u.version != 3) return;
      for (uint32_t i = 0; i < u.tiles._length; ++i)
        changed.push_back(transport::FromIdl(u.tiles._buffer[i]));
    });
    return !changed.empty();
  }));
  EXPECT_NE(std::find(changed.begin(), changed.end(), mosaic::TileKey{0, 1, 1}), changed.end());
  EXPECT_LT(ChangedPartDifference(**client, 6, 3, scene_.old_floor), 1.0);
}

TEST_F(MapServerPatchRemap, AForgedVehicleChangesNothingAndIsQuarantined) {
  auto forger = transport::PatchClient::Create(server_.participant(), "forger");
  ASSERT_TRUE(forger.ok());
  ASSERT_TRUE(Eventually([&] { return (*forger)->ServerMatched(); }));
  uint64_t sequence = 0;
  for (cv::Point centre : {cv::Point(490, 425), cv::Point(520, 400)}) {
    for (const auto& forged : mapping::testing::ForgedPatches(scene_, centre)) {
      ASSERT_TRUE(testing::SendPatch(**forger, testing::ToSend(forged.patch, ++sequence)));
    }
  }
  ASSERT_TRUE(Eventually([&] { return server_.HealthCounter("patches_stored") == sequence; }));
  SendTheTwoPatches();  // agv-1's true views of the changed floor
  auto store = mosaic::TileStore::Open(server_.mosaic_path(), mosaic::OpenMode::kReadOnly);
  ASSERT_TRUE(store.ok());
  const std::vector<std::uint8_t> far_tile_before = *(*store)->ReadTileBytes({0, 3, 3});
  const testing::CommandResult remap = Remap(RegionAroundChange());
  ASSERT_EQ(remap.exit_code, 0) << remap.err;
  const auto outcome = nlohmann::json::parse(remap.out);
  EXPECT_EQ(outcome["new_version"], 2);
  EXPECT_EQ(outcome["patches_folded"], 2);
  EXPECT_EQ(outcome["patches_rejected"], sequence);
  const std::string message = outcome["message"];
  EXPECT_NE(message.find("agv-1: 2 folded"), std::string::npos) << message;
  EXPECT_NE(message.find("forger: 0 folded, 12 refused"), std::string::npos) << message;
  EXPECT_NE(message.find("QUARANTINED"), std::string::npos) << message;
  // Only the true views changed the floor: the changed area shows the new floor.
  ASSERT_TRUE((*store)->Refresh().ok());
  const cv::Mat tile = *mosaic::DecodeTile(*(*store)->ReadTileBytes({0, 1, 1}), 256);
  const cv::Rect part = scene_.change & cv::Rect(256, 256, 256, 256);
  cv::Mat diff;
  cv::absdiff(tile(part - cv::Point(256, 256)), scene_.new_floor(part), diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
  EXPECT_EQ(*(*store)->ReadTileBytes({0, 3, 3}), far_tile_before);
  EXPECT_EQ(server_.HealthCounter("vehicles_quarantined"), 1u);
  EXPECT_EQ(server_.HealthCounter("patches_refused"), sequence);
  EXPECT_NE(server_.HealthIssue().find("vehicle_quarantined: forger"), std::string::npos);
  // The forger's next patch is refused on arrival, even a true view.
  ASSERT_TRUE(testing::SendPatch(**forger, PatchAt(++sequence, {490, 425}, {})));
  std::optional<transport::ReceivedAck> refused;
  ASSERT_TRUE(Eventually([&] {
    auto acks = (*forger)->TakeAcks();
    for (const auto& ack : acks.ok() ? *acks : std::vector<transport::ReceivedAck>{}) {
      if (ack.sequence == sequence) refused = ack;
    }
    return refused.has_value();
  }));
  EXPECT_EQ(refused->status, fleetloc_PATCH_REJECTED);
  EXPECT_NE(refused->reason.find("quarantined"), std::string::npos) << refused->reason;
  EXPECT_EQ(server_.HealthCounter("rejected_patch_quarantined"), 1u);
  // A maintainer releases it; the alert clears.
  const testing::CommandResult release =
      testing::RunFleetctl("mosaic vehicles " + server_.mosaic_path() + " --release forger");
  ASSERT_EQ(release.exit_code, 0) << release.err;
  EXPECT_EQ(nlohmann::json::parse(release.out)["forger"]["quarantined"], false);
  EXPECT_TRUE(
      Eventually([&] { return server_.HealthIssue().find("quarantined") == std::string::npos; }));
}

TEST_F(MapServerPatchRemap, BadRemapCommandsAreRejected) {
  // fleetctl refuses an inverted region itself; a forged command gets past it to the server.
  const testing::CommandResult inverted = Remap("0.3,0.3,0.2,0.2");
  EXPECT_EQ(inverted.exit_code, 2);
  EXPECT_NE(inverted.err.find("x_min < x_max"), std::string::npos) << inverted.err;
  auto forger = transport::RemapClient::Create(server_.participant());
  ASSERT_TRUE(forger.ok()) << forger.status().message();
  ASSERT_TRUE(Eventually([&] { return (*forger)->ServerMatched(); }));
  fleetloc_RemapCommand forged{};
  forged.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  forged.command_id = 77;
  forged.region = {0.3, 0.3, 0.2, 0.2};
  ASSERT_TRUE((*forger)->SendRaw(forged).ok());
  bool rejected = false;
  ASSERT_TRUE(Eventually([&] {
    auto statuses = (*forger)->TakeStatuses();
    for (const auto& s : statuses.ok() ? *statuses : std::vector<transport::RemapProgress>{}) {
      if (s.command_id == 77 && s.state == fleetloc_REMAP_REJECTED) {
        rejected = true;
        EXPECT_NE(s.message.find("empty or inverted"), std::string::npos) << s.message;
      }
    }
    return rejected;
  }));
  const testing::CommandResult outside = Remap("5,5,6,6");
  EXPECT_EQ(outside.exit_code, 2);
  EXPECT_NE(outside.err.find("outside"), std::string::npos) << outside.err;
  const testing::CommandResult foreign =
      Remap(RegionAroundChange(), "--mosaic-id 0123456789abcdef0123456789abcdef");
  EXPECT_EQ(foreign.exit_code, 2);
  EXPECT_NE(foreign.err.find("unknown mosaic"), std::string::npos) << foreign.err;
  EXPECT_EQ(server_.HealthCounter("rejected_remap_command"), 3u);
}

}  // namespace
}  // namespace fleetloc
