// The map server as its own process, driven through DDS on loopback (own domain id): mosaic
// announcement, tiles byte-identical to the store, replies confined to the requesting vehicle,
// and bad requests answered with an error status and counted in the server's health.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "map_server_fixture.h"
#include "mosaic/tile_store.h"
#include "transport/dds_tile_loader.h"
#include "transport/tile_client.h"
#include "transport/topic_names.h"
#include "transport/vehicle_streams.h"
#include "transport/wire_util.h"

namespace fleetloc {
namespace {

using testing::Eventually;
using transport::ReceivedTile;
using transport::TileClient;

constexpr uint32_t kDomain = 81;

class MapServerDds : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const cv::Mat floor =
        cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
    fixture_ = new testing::MapServerFixture("map_server_dds", floor, kDomain, 0.0005, 128);
    layout_ = fixture_->layout();
    mosaic_path_ = fixture_->mosaic_path();
    participant_ = &fixture_->participant();
  }
  static void TearDownTestSuite() { delete fixture_; }

  std::unique_ptr<TileClient> Client(const std::string& vehicle_id) {
    auto client = TileClient::Create(*participant_, vehicle_id);
    EXPECT_TRUE(client.ok()) << client.status().message();
    EXPECT_TRUE(Eventually([&] { return (*client)->RequestsMatched(); }));
    return std::move(client).value();
  }

  // A vehicle's view of the mosaic through `loader` (tiles over DDS).
  static mosaic::MosaicView ViewOver(transport::DdsTileLoader& loader) {
    return mosaic::MosaicView(layout_, loader.AsTileLoader(),
                              std::make_shared<mosaic::TileCache>(size_t{8} << 20));
  }
  // The mosaic read straight from the store: what a view over DDS must equal.
  static mosaic::MosaicView LocalView() {
    auto store = std::shared_ptr<mosaic::TileStore>(
        std::move(mosaic::TileStore::Open(mosaic_path_, mosaic::OpenMode::kReadOnly)).value());
    return mosaic::MosaicView(layout_, mosaic::MakeTileLoader(store),
                              std::make_shared<mosaic::TileCache>(size_t{8} << 20));
  }

  // Requests `keys` and collects replies until `expected` tiles of request `id` arrived.
  std::vector<ReceivedTile> Fetch(TileClient& client, uint32_t id,
                                  const std::vector<mosaic::TileKey>& keys, size_t expected,
                                  const std::string& mosaic_id = "") {
    EXPECT_TRUE(client.Request(id, mosaic_id, keys).ok());
    std::vector<ReceivedTile> got;
    Eventually([&] {
      auto tiles = client.TakeTiles();
      EXPECT_TRUE(tiles.ok());
      for (auto& t : *tiles) {
        if (t.request_id == id) got.push_back(std::move(t));
      }
      return got.size() >= expected;
    });
    return got;
  }

  uint64_t HealthCounter(const std::string& name) { return fixture_->HealthCounter(name); }

  static testing::MapServerFixture* fixture_;
  static std::string mosaic_path_;
  static mosaic::MosaicLayout layout_;
  static transport::Participant* participant_;
};

testing::MapServerFixture* MapServerDds::fixture_ = nullptr;
std::string MapServerDds::mosaic_path_;
mosaic::MosaicLayout MapServerDds::layout_;
transport::Participant* MapServerDds::participant_ = nullptr;

TEST_F(MapServerDds, AnnouncesTheMosaicToLateJoiners) {
  auto client = Client("veh-info");
  std::optional<fleetloc_MosaicInfo> info;
  ASSERT_TRUE(Eventually([&] { return (info = client->LatestMosaicInfo()).has_value(); }));
  EXPECT_EQ(transport::GetBounded(info->mosaic_id), layout_.mosaic_id);
  EXPECT_EQ(transport::GetBounded(info->server_id), "map-t");
  EXPECT_EQ(info->width_px, layout_.width_px);
  EXPECT_EQ(info->levels, layout_.levels);
  EXPECT_EQ(info->resolution, 0.0005);
  EXPECT_EQ(info->version, layout_.version);
}

TEST_F(MapServerDds, FleetctlMosaicInfoListsTheServedMosaic) {
  const testing::CommandResult r =
      testing::RunFleetctl("mosaic info --wait 1 --domain " + std::to_string(kDomain));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  ASSERT_EQ(json["servers"].size(), 1u);
  EXPECT_EQ(json["servers"][0]["mosaic_id"], layout_.mosaic_id);
  EXPECT_EQ(json["servers"][0]["server_id"], "map-t");
  EXPECT_EQ(json["servers"][0]["width"], layout_.width_px);
  const testing::CommandResult none = testing::RunFleetctl("mosaic info --wait 0.3 --domain 99");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("no map server"), std::string::npos) << none.err;
}

TEST_F(MapServerDds, ServesEveryTileByteIdenticalToTheStore) {
  auto store = mosaic::TileStore::Open(mosaic_path_, mosaic::OpenMode::kReadOnly);
  ASSERT_TRUE(store.ok());
  std::vector<mosaic::TileKey> keys;
  for (int level = 0; level < layout_.levels; ++level) {
    mosaic::TilesCovering(layout_, level,
                          {0, 0, layout_.LevelWidth(level), layout_.LevelHeight(level)})
        .ForEach([&](const mosaic::TileKey& k) { keys.push_back(k); });
  }
  auto client = Client("veh-all");
  const auto got = Fetch(*client, 1, keys, keys.size());
  ASSERT_EQ(got.size(), keys.size());
  for (const ReceivedTile& tile : got) {
    ASSERT_EQ(tile.status, fleetloc_TILE_OK) << mosaic::ToString(tile.key) << " " << tile.error;
    auto expected = (*store)->ReadTileBytes(tile.key);
    ASSERT_TRUE(expected.ok());
    EXPECT_EQ(tile.data, *expected) << mosaic::ToString(tile.key);
    EXPECT_EQ(tile.mosaic_id, layout_.mosaic_id);
  }
}

TEST_F(MapServerDds, AVehicleViewOverDdsTilesReadsWhatTheStoreHolds) {
  auto client = Client("veh-view");
  transport::DdsTileLoader loader(client.get(), layout_.mosaic_id, layout_.tile_size_px,
                                  std::chrono::seconds(5));
  mosaic::MosaicView over_dds = ViewOver(loader);
  mosaic::MosaicView local = LocalView();
  ASSERT_TRUE(loader.Prefetch({{0, 0, 0}, {0, 1, 0}}).ok());
  for (const cv::Rect& block :
       {cv::Rect(10, 20, 300, 200), cv::Rect(-50, 400, 200, 200), cv::Rect(200, 100, 250, 250)}) {
    for (int level : {0, 1}) {
      EXPECT_EQ(
          cv::norm(over_dds.ReadBlock(level, block), local.ReadBlock(level, block), cv::NORM_INF),
          0)
          << block << " level " << level;
    }
  }
  EXPECT_GT(loader.stats().received, 4);
  EXPECT_EQ(loader.stats().timeouts, 0);
  EXPECT_EQ(loader.stats().errors, 0);
}

TEST_F(MapServerDds, PrefetchedTilesStayEncodedUntilDecodedAFewAtATimeOrLoaded) {
  auto client = Client("veh-decode");
  transport::DdsTileLoader loader(client.get(), layout_.mosaic_id, layout_.tile_size_px,
                                  std::chrono::seconds(5));
  mosaic::MosaicView over_dds = ViewOver(loader);
  mosaic::MosaicView local = LocalView();
  const std::vector<mosaic::TileKey> ahead{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}};
  ASSERT_TRUE(loader.Prefetch(ahead).ok());
  ASSERT_TRUE(Eventually([&] { return loader.Poll().ok() && loader.pending() == 0; }));
  EXPECT_EQ(loader.encoded(), ahead.size());  // arrived, not decoded by the poll
  Result<size_t> left = loader.DecodeArrived(1);
  ASSERT_TRUE(left.ok());
  EXPECT_EQ(*left, ahead.size() - 1);
  ASSERT_TRUE(loader.Prefetch(ahead).ok());  // nothing asked again: they are all here
  EXPECT_EQ(loader.stats().requested, static_cast<long long>(ahead.size()));
  // The view takes a decoded tile and one still encoded alike, without waiting for the network.
  const cv::Rect block(10, 10, 2 * layout_.tile_size_px - 20, layout_.tile_size_px - 20);
  EXPECT_EQ(cv::norm(over_dds.ReadBlock(0, block), local.ReadBlock(0, block), cv::NORM_INF), 0);
  left = loader.DecodeArrived(10);
  ASSERT_TRUE(left.ok());
  EXPECT_EQ(*left, 0u);
  EXPECT_EQ(loader.encoded(), 0u);
  EXPECT_EQ(loader.stats().waited, 0);
  const cv::Rect lower(10, layout_.tile_size_px + 10, 2 * layout_.tile_size_px - 20, 50);
  EXPECT_EQ(cv::norm(over_dds.ReadBlock(0, lower), local.ReadBlock(0, lower), cv::NORM_INF), 0);
  EXPECT_EQ(loader.stats().waited, 0);
  EXPECT_EQ(loader.stats().errors, 0);
}

TEST(DdsTileLoader, UnreachableServerTimesOutWithAClearError) {
  auto participant = transport::Participant::Create(kDomain + 10);  // nobody serves there
  ASSERT_TRUE(participant.ok());
  auto client = TileClient::Create(*participant, "veh-lonely");
  ASSERT_TRUE(client.ok());
  transport::DdsTileLoader loader(client->get(), "0123456789abcdef0123456789abcdef", 128,
                                  std::chrono::milliseconds(200));
  Result<cv::Mat> tile = loader.Load({0, 0, 0});
  ASSERT_FALSE(tile.ok());
  EXPECT_EQ(tile.status().code(), StatusCode::kInternal);
  EXPECT_NE(tile.status().message().find("no answer"), std::string::npos);
  EXPECT_EQ(loader.stats().timeouts, 1);
}

TEST_F(MapServerDds, RepliesReachOnlyTheRequestingVehicle) {
  std::vector<std::unique_ptr<TileClient>> fleet;
  for (int i = 0; i < 5; ++i) fleet.push_back(Client("veh-" + std::to_string(i)));
  const std::vector<mosaic::TileKey> keys = {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const auto got = Fetch(*fleet[0], 7, keys, keys.size());
  EXPECT_EQ(got.size(), keys.size());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (int i = 1; i < 5; ++i) {
    auto others = fleet[i]->TakeTiles();
    ASSERT_TRUE(others.ok());
    EXPECT_TRUE(others->empty()) << "vehicle " << i << " received another vehicle's tiles";
  }
}

TEST_F(MapServerDds, BadRequestsGetAnErrorStatusAndAreCounted) {
  auto client = Client("veh-bad");
  const int cols = mosaic::TileColumns(layout_, 0);
  auto out_of_range = Fetch(*client, 11, {{0, cols, 0}, {layout_.levels, 0, 0}, {0, -1, 0}}, 3);
  ASSERT_EQ(out_of_range.size(), 3u);
  for (const auto& t : out_of_range) {
    EXPECT_EQ(t.status, fleetloc_TILE_OUT_OF_RANGE);
    EXPECT_NE(t.error.find("outside"), std::string::npos) << t.error;
    EXPECT_TRUE(t.data.empty());
  }
  auto unknown = Fetch(*client, 12, {{0, 0, 0}}, 1, "0123456789abcdef0123456789abcdef");
  ASSERT_EQ(unknown.size(), 1u);
  EXPECT_EQ(unknown[0].status, fleetloc_TILE_UNKNOWN_MOSAIC);
  EXPECT_GE(HealthCounter("rejected_tile_range"), 3u);
  EXPECT_GE(HealthCounter("rejected_unknown_mosaic"), 1u);
  // The server is still serving after them.
  auto good = Fetch(*client, 13, {{0, 0, 0}}, 1);
  ASSERT_EQ(good.size(), 1u);
  EXPECT_EQ(good[0].status, fleetloc_TILE_OK);
}

TEST_F(MapServerDds, ForgedRequestsAreRejectedAndCounted) {
  auto topic = transport::Topic<fleetloc_TileRequest>::Create(*participant_,
                                                              transport::topics::kTileRequest);
  auto writer = transport::VehicleStreamWriter<fleetloc_TileRequest>::Create(
      *participant_, "veh-x", *topic, transport::CommandQos());
  ASSERT_TRUE(Eventually([&] { return writer->MatchedReaders() > 0; }));
  const uint64_t before = HealthCounter("rejected_tile_request");
  const uint64_t before_partition = HealthCounter("rejected_vehicle_partition");
  // Not the id of the partition it is written in (veh-x's): rejected before it is read.
  fleetloc_TileRequest bad_id{};
  bad_id.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  transport::SetBounded(bad_id.vehicle_id, "veh*");  // a partition wildcard
  fleetloc_TileRequest bad_version{};
  bad_version.wire_version = 999;
  transport::SetBounded(bad_version.vehicle_id, "veh-x");
  ASSERT_TRUE(writer->Write(bad_id).ok());
  ASSERT_TRUE(writer->Write(bad_version).ok());
  EXPECT_TRUE(Eventually([&] { return HealthCounter("rejected_tile_request") >= before + 1; }));
  EXPECT_TRUE(Eventually(
      [&] { return HealthCounter("rejected_vehicle_partition") >= before_partition + 1; }));
}

}  // namespace
}  // namespace fleetloc
