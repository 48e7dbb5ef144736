// PatchObservation and PatchAck conversions: every field survives the trip through the wire
// types.
#include "transport/patch_messages.h"

#include <gtest/gtest.h>

#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

// A patch with a distinct value in every field (the covariance 0.1 … 0.9, row-major).
const PatchToSend kPatch{.sequence = 1234567,
                         .stamp_s = 1700000000.25,
                         .mosaic_id = "hall_a",
                         .mosaic_version = 8,
                         .pose = {1.5, -2.25, 0.75},
                         .covariance = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9},
                         .quality = 0.8f,
                         .resolution_m = 0.002,
                         .png = {0x89, 'P', 'N', 'G', 1, 2, 3}};

TEST(PatchMessages, ObservationCarriesEveryFieldOfThePatch) {
  const PatchToSend& p = kPatch;
  const fleetloc_PatchObservation s = ToIdl(p, "veh-7");
  EXPECT_EQ(s.wire_version, fleetloc_CURRENT_WIRE_VERSION);
  EXPECT_EQ(GetBounded(s.vehicle_id), "veh-7");
  EXPECT_EQ(GetBounded(s.mosaic_id), "hall_a");
  EXPECT_EQ(s.mosaic_version, 8);
  EXPECT_EQ(GetBounded(s.encoding), "png");
  EXPECT_DOUBLE_EQ(s.resolution, 0.002);
  EXPECT_EQ(s.image._buffer, p.png.data());                // borrowed, not copied
  EXPECT_EQ(CovarianceFromIdl(s)(0, 1), p.covariance[1]);  // row-major
  EXPECT_EQ(CovarianceFromIdl(s)(1, 0), p.covariance[3]);
}

TEST(PatchMessages, RecordRoundTripsThePatch) {
  const PatchToSend& p = kPatch;
  const fleetloc_PatchObservation s = ToIdl(p, "veh-7");
  mosaic::PatchRecord record = RecordFromIdl(s);
  EXPECT_EQ(record.vehicle_id, "veh-7");
  EXPECT_EQ(record.sequence, 1234567);
  EXPECT_NEAR(record.stamp_s, 1700000000.25, 1e-6);
  EXPECT_DOUBLE_EQ(record.pose.x, 1.5);
  EXPECT_DOUBLE_EQ(record.pose.y, -2.25);
  EXPECT_DOUBLE_EQ(record.pose.theta, 0.75);
  for (int i = 0; i < 9; ++i) EXPECT_DOUBLE_EQ(record.covariance(i / 3, i % 3), p.covariance[i]);
  EXPECT_FLOAT_EQ(static_cast<float>(record.quality), 0.8f);
  EXPECT_TRUE(record.png.empty());
  CopyPng(s, &record);
  EXPECT_EQ(record.png, p.png);
}

TEST(PatchMessages, AckRoundTripsAndNamesItsServer) {
  const PatchAckReply ack{77, fleetloc_PATCH_REJECTED, "pose not finite"};
  const fleetloc_PatchAck message = ToIdl(ack, "veh-7");
  EXPECT_EQ(message.wire_version, fleetloc_CURRENT_WIRE_VERSION);
  EXPECT_EQ(GetBounded(message.vehicle_id), "veh-7");
  const ReceivedAck back = FromIdl(message, "ms-east");
  EXPECT_EQ(back.sequence, 77u);
  EXPECT_EQ(back.server_id, "ms-east");
  EXPECT_EQ(back.status, fleetloc_PATCH_REJECTED);
  EXPECT_EQ(back.reason, "pose not finite");
  EXPECT_EQ(FromIdl(ToIdl(PatchAckReply{3, fleetloc_PATCH_STORED, ""}, "v"), "").status,
            fleetloc_PATCH_STORED);
}

}  // namespace
}  // namespace fleetloc::transport
