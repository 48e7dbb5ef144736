// RemapCommand and RemapStatus conversions: every field survives the trip through the wire types.
#include "transport/remap_messages.h"

#include <gtest/gtest.h>

#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

TEST(RemapMessages, CommandCarriesTheRequestAndItsId) {
  const RemapRequest request{1.5, -2.0, 3.25, 4.0, true, "hall_a", "maintainer"};
  const fleetloc_RemapCommand c = ToIdl(request, 0x1234567890abcdefULL);
  EXPECT_EQ(c.wire_version, fleetloc_CURRENT_WIRE_VERSION);
  EXPECT_EQ(c.command_id, 0x1234567890abcdefULL);
  EXPECT_EQ(GetBounded(c.mosaic_id), "hall_a");
  EXPECT_EQ(GetBounded(c.requester), "maintainer");
  EXPECT_DOUBLE_EQ(c.region.x_min, 1.5);
  EXPECT_DOUBLE_EQ(c.region.y_min, -2.0);
  EXPECT_DOUBLE_EQ(c.region.x_max, 3.25);
  EXPECT_DOUBLE_EQ(c.region.y_max, 4.0);
  EXPECT_EQ(c.mode, fleetloc_REMAP_REPLACE);
  EXPECT_EQ(ToIdl(RemapRequest{}, 1).mode, fleetloc_REMAP_BLEND);
}

TEST(RemapMessages, StatusRoundTripsEveryFieldAndTakesTheGivenStamp) {
  RemapProgress p;
  p.command_id = 42;
  p.server_id = "map-b";
  p.state = fleetloc_REMAP_DONE;
  p.phase = "done";
  p.progress = 1.0;
  p.new_version = 7;
  p.tiles_changed = 12;
  p.patches_folded = 5;
  p.patches_rejected = 1;
  p.message = "folded 5 patches";
  const fleetloc_RemapStatus s = ToIdl(p, ToStamp(1700000000.5));
  EXPECT_EQ(s.wire_version, fleetloc_CURRENT_WIRE_VERSION);
  const RemapProgress back = FromIdl(s);
  EXPECT_EQ(back.command_id, 42u);
  EXPECT_EQ(back.server_id, "map-b");
  EXPECT_EQ(back.state, fleetloc_REMAP_DONE);
  EXPECT_TRUE(back.final());
  EXPECT_EQ(back.phase, "done");
  EXPECT_FLOAT_EQ(back.progress, 1.0);
  EXPECT_EQ(back.new_version, 7);
  EXPECT_EQ(back.tiles_changed, 12u);
  EXPECT_EQ(back.patches_folded, 5u);
  EXPECT_EQ(back.patches_rejected, 1u);
  EXPECT_EQ(back.message, "folded 5 patches");
  EXPECT_NEAR(back.t, 1700000000.5, 1e-6);
  EXPECT_STREQ(RemapStateName(back.state), "done");
}

}  // namespace
}  // namespace fleetloc::transport
