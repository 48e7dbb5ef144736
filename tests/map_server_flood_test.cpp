// One vehicle flooding a map_server process with patches: its disk use stops at its quota (the
// surplus is counted and not acknowledged, so an honest vehicle would keep it), its rate is
// limited, while another vehicle's tiles keep coming and its patch is still stored; and patches
// whose header declares what may not be decoded (16-bit RGBA, a huge size) are refused unread.
// Latencies under a flood: `fleetctl bench patch-flood` (docs/benchmarks.md).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "changed_floor_patches.h"
#include "map_server_fixture.h"
#include "mosaic/patch_store.h"
#include "transport/tile_client.h"

namespace fleetloc {
namespace {

using testing::Eventually;
using testing::Scene;
constexpr uint32_t kDomain = 85;

// A 512 × 512 patch of noise (about 256 KiB of PNG: noise does not compress) claiming the scene's
// centre, numbered `sequence`.
transport::PatchToSend NoisePatch(const Scene& scene, uint64_t sequence) {
  transport::PatchToSend p = testing::ScenePatch(scene, sequence, {512, 512}, {});
  cv::Mat noise(512, 512, CV_8UC1);
  cv::randu(noise, 0, 256);
  p.png = *mosaic::EncodeTile(noise);
  return p;
}

class MapServerFlood : public ::testing::Test {
 protected:
  // A quota of 2 MB per vehicle and a generous rate, so the quota is what stops the flood.
  MapServerFlood()
      : server_(
            "map_server_flood", scene_.old_floor, kDomain, 0.0005, 256,
            R"("patch_intake": {"patches_per_s": 200, "burst": 200, "max_mb_per_vehicle": 2, "queue": 64})") {
  }

  Scene scene_;
  testing::MapServerFixture server_;
};

TEST_F(MapServerFlood, AFloodingVehicleStopsAtItsQuotaWhileOthersAreServed) {
  auto flooder = transport::PatchClient::Create(server_.participant(), "flood");
  auto honest = transport::PatchClient::Create(server_.participant(), "agv-1");
  auto tiles = transport::TileClient::Create(server_.participant(), "agv-2");
  ASSERT_TRUE(flooder.ok() && honest.ok() && tiles.ok());
  ASSERT_TRUE(Eventually([&] {
    return (*flooder)->ServerMatched() && (*honest)->ServerMatched() && (*tiles)->RequestsMatched();
  }));
  // 60 patches of about 256 KiB (15 MB) as fast as the writer takes them, tiles asked for
  // meanwhile.
  const transport::PatchToSend first = NoisePatch(scene_, 1);
  const size_t patch_bytes = first.png.size();
  int tiles_answered = 0;
  uint32_t request = 0;
  for (uint64_t sequence = 1; sequence <= 60; ++sequence) {
    transport::PatchToSend p = first;
    p.sequence = sequence;
    ASSERT_TRUE(testing::SendPatch(**flooder, p));
    if (sequence % 6 == 0) {  // ten different tiles (a tile reader keeps the newest of each)
      const int i = static_cast<int>(request++);
      ASSERT_TRUE((*tiles)->Request(request, "", {{0, i % 4, i / 4}}).ok());
    }
  }
  ASSERT_TRUE(testing::SendPatch(**honest, testing::ScenePatch(scene_, 1, {490, 425}, {})));
  ASSERT_TRUE(Eventually([&] {
    auto taken = (*tiles)->TakeTiles();
    tiles_answered += taken.ok() ? static_cast<int>(taken->size()) : 0;
    return tiles_answered == 10;
  }));
  // The flooder's disk use stopped at its quota; what was over it is counted, not stored.
  ASSERT_TRUE(Eventually([&] { return server_.HealthCounter("patches_stored") >= 2; }));
  ASSERT_TRUE(Eventually([&] {
    return server_.HealthCounter("patches_stored") +
               server_.HealthCounter("patches_over_vehicle_quota") +
               server_.HealthCounter("patches_duplicate") >=
           61;
  }));
  auto store = mosaic::PatchStore::Open(server_.mosaic_path());
  ASSERT_TRUE(store.ok());
  const auto usage = (*store)->UsageByVehicle();
  ASSERT_TRUE(usage.ok());
  EXPECT_LE(usage->at("flood").bytes, 2LL << 20);
  EXPECT_GE(usage->at("flood").bytes, (2LL << 20) - static_cast<long long>(patch_bytes));
  EXPECT_EQ(usage->at("flood").patches, static_cast<long long>((2u << 20) / patch_bytes));
  EXPECT_GT(server_.HealthCounter("patches_over_vehicle_quota"), 40u);
  EXPECT_EQ(usage->at("agv-1").patches, 1);  // the honest vehicle's budget is its own
  // The flooder heard back only about the patches stored (it would send the others again).
  long long acked = 0;
  EXPECT_TRUE(Eventually([&] {
    auto acks = (*flooder)->TakeAcks();
    acked += acks.ok() ? static_cast<long long>(acks->size()) : 0;
    return acked >= usage->at("flood").patches;
  }));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  auto late = (*flooder)->TakeAcks();
  EXPECT_EQ(acked + (late.ok() ? static_cast<long long>(late->size()) : 0),
            usage->at("flood").patches);
}

TEST_F(MapServerFlood, PatchesDeclaringWhatMayNotBeDecodedAreRefusedUnread) {
  auto vehicle = transport::PatchClient::Create(server_.participant(), "agv-3");
  ASSERT_TRUE(vehicle.ok());
  ASSERT_TRUE(Eventually([&] { return (*vehicle)->ServerMatched(); }));
  transport::PatchToSend deep = testing::ScenePatch(scene_, 1, {490, 425}, {});
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(240, 320, CV_16UC4, cv::Scalar(1, 2, 3, 4)), deep.png));
  transport::PatchToSend huge = testing::ScenePatch(scene_, 2, {490, 425}, {});
  for (size_t at : {16u, 20u}) {
    huge.png[at] = 0;
    huge.png[at + 1] = 0;
    huge.png[at + 2] = 0x75;
    huge.png[at + 3] = 0x30;
  }
  ASSERT_TRUE(testing::SendPatch(**vehicle, deep));
  ASSERT_TRUE(testing::SendPatch(**vehicle, huge));
  std::map<uint64_t, transport::ReceivedAck> acks;
  ASSERT_TRUE(Eventually([&] {
    auto taken = (*vehicle)->TakeAcks();
    for (const auto& a : taken.ok() ? *taken : std::vector<transport::ReceivedAck>{})
      acks[a.sequence] = a;
    return acks.size() == 2;
  }));
  EXPECT_EQ(acks.at(1).status, fleetloc_PATCH_REJECTED);
  EXPECT_NE(acks.at(1).reason.find("16-bit, 4 channels"), std::string::npos) << acks.at(1).reason;
  EXPECT_EQ(acks.at(2).status, fleetloc_PATCH_REJECTED);
  EXPECT_NE(acks.at(2).reason.find("30000x30000"), std::string::npos) << acks.at(2).reason;
}

}  // namespace
}  // namespace fleetloc
