// TileRequest and Tile conversions: every field survives the trip through the wire types.
#include "transport/tile_messages.h"

#include <gtest/gtest.h>

#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

TEST(TileMessages, RequestRoundTripsItsTilesAndIds) {
  const TileAsk ask{"veh-7", 99, "hall_a", {{0, 3, 4}, {2, 0, 1}, {5, 12, 9}}};
  std::vector<fleetloc_TileAddress> addresses;
  const fleetloc_TileRequest request = ToIdl(ask, &addresses);
  EXPECT_EQ(request.wire_version, fleetloc_CURRENT_WIRE_VERSION);
  EXPECT_EQ(request.tiles._length, 3u);
  EXPECT_EQ(request.tiles._buffer, addresses.data());  // borrowed, not owned
  EXPECT_FALSE(request.tiles._release);
  const TileAsk back = FromIdl(request);
  EXPECT_EQ(back.vehicle_id, "veh-7");
  EXPECT_EQ(back.request_id, 99u);
  EXPECT_EQ(back.mosaic_id, "hall_a");
  EXPECT_EQ(back.tiles, ask.tiles);
}

TEST(TileMessages, EmptyRequestHasNoTiles) {
  std::vector<fleetloc_TileAddress> addresses{{1, 2, 3}};
  const fleetloc_TileRequest request = ToIdl(TileAsk{"v", 1, "", {}}, &addresses);
  EXPECT_EQ(request.tiles._length, 0u);
  EXPECT_TRUE(FromIdl(request).tiles.empty());
  EXPECT_TRUE(FromIdl(request).mosaic_id.empty());
}

TEST(TileMessages, ReplyRoundTripsEveryFieldAndTheBytes) {
  const std::vector<std::uint8_t> bytes{0x89, 'P', 'N', 'G', 0, 255};
  TileAnswer answer{"veh-7", 99, {3, 10, 11}, "hall_a", 42};
  answer.status = fleetloc_TILE_OK;
  answer.data = bytes;
  const fleetloc_Tile tile = ToIdl(answer);
  EXPECT_EQ(tile.wire_version, fleetloc_CURRENT_WIRE_VERSION);
  EXPECT_EQ(GetBounded(tile.vehicle_id), "veh-7");
  EXPECT_EQ(tile.data._buffer, bytes.data());  // borrowed, not copied
  const ReceivedTile back = FromIdl(tile);
  EXPECT_EQ(back.key, (mosaic::TileKey{3, 10, 11}));
  EXPECT_EQ(back.request_id, 99u);
  EXPECT_EQ(back.status, fleetloc_TILE_OK);
  EXPECT_EQ(back.version, 42);
  EXPECT_EQ(back.mosaic_id, "hall_a");
  EXPECT_TRUE(back.error.empty());
  EXPECT_EQ(back.data, bytes);
}

TEST(TileMessages, ErrorReplyCarriesItsStatusAndMessageWithoutData) {
  TileAnswer answer{"veh-7", 5, {0, 99, 99}, "hall_a", 3};
  answer.status = fleetloc_TILE_OUT_OF_RANGE;
  answer.error = "outside the mosaic's tile grid";
  const fleetloc_Tile tile = ToIdl(answer);
  EXPECT_EQ(tile.data._length, 0u);
  const ReceivedTile back = FromIdl(tile);
  EXPECT_EQ(back.status, fleetloc_TILE_OUT_OF_RANGE);
  EXPECT_EQ(back.error, "outside the mosaic's tile grid");
  EXPECT_TRUE(back.data.empty());
}

}  // namespace
}  // namespace fleetloc::transport
