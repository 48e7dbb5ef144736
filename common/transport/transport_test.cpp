// Transport layer on loopback: typed round trip, large samples, partitions, durability, bad config.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <numeric>
#include <thread>
#include <vector>

#include "base/eventually.h"
#include "transport/typed_io.h"
#include "transport/waitset.h"

namespace fleetloc::transport {
namespace {

constexpr uint32_t kDomain = 71;  // this test binary's own domain

using testing::Eventually;

template <typename T>
T Unwrap(Result<T> result) {
  EXPECT_TRUE(result.ok()) << result.status().message();
  return std::move(result).value();
}

TEST(Transport, VehiclePoseRoundTripBetweenParticipants) {
  Participant a = Unwrap(Participant::Create(kDomain));
  Participant b = Unwrap(Participant::Create(kDomain));
  auto topic_a = Unwrap(Topic<fleetloc_VehiclePose>::Create(a, "test_pose"));
  auto topic_b = Unwrap(Topic<fleetloc_VehiclePose>::Create(b, "test_pose"));
  auto writer = Unwrap(Writer<fleetloc_VehiclePose>::Create(a.get(), topic_a, CommandQos()));
  auto reader = Unwrap(Reader<fleetloc_VehiclePose>::Create(b.get(), topic_b, CommandQos()));
  ASSERT_TRUE(Eventually([&] { return writer.MatchedReaders() == 1; }));
  fleetloc_VehiclePose pose{};
  pose.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  std::snprintf(pose.vehicle_id, sizeof pose.vehicle_id, "agv-7");
  pose.x = 1.25;
  pose.y = -2.5;
  pose.theta = 0.125;
  pose.covariance[8] = 1e-4;
  pose.lock_state = fleetloc_LOCK_TRACKING;
  ASSERT_TRUE(writer.Write(pose).ok());
  std::vector<fleetloc_VehiclePose> got;
  ASSERT_TRUE(Eventually([&] {
    (void)reader.Take(
        [&](const fleetloc_VehiclePose& p, const dds_sample_info_t&) { got.push_back(p); });
    return !got.empty();
  }));
  EXPECT_STREQ(got[0].vehicle_id, "agv-7");
  EXPECT_EQ(got[0].x, 1.25);
  EXPECT_EQ(got[0].y, -2.5);
  EXPECT_EQ(got[0].theta, 0.125);
  EXPECT_EQ(got[0].covariance[8], 1e-4);
  EXPECT_EQ(got[0].wire_version, fleetloc_CURRENT_WIRE_VERSION);
}

TEST(Transport, LargeTileSampleArrivesIntact) {
  Participant a = Unwrap(Participant::Create(kDomain));
  Participant b = Unwrap(Participant::Create(kDomain));
  auto topic_a = Unwrap(Topic<fleetloc_Tile>::Create(a, "test_tile"));
  auto topic_b = Unwrap(Topic<fleetloc_Tile>::Create(b, "test_tile"));
  auto writer = Unwrap(Writer<fleetloc_Tile>::Create(a.get(), topic_a, BulkQos()));
  auto reader = Unwrap(Reader<fleetloc_Tile>::Create(b.get(), topic_b, BulkQos()));
  ASSERT_TRUE(Eventually([&] { return writer.MatchedReaders() == 1; }));
  std::vector<uint8_t> payload(300 * 1024);
  for (size_t i = 0; i < payload.size(); ++i)
    payload[i] = static_cast<uint8_t>(i * 2654435761u >> 13);
  fleetloc_Tile tile{};
  tile.level = 2;
  tile.col = 3;
  tile.row = 4;
  tile.data._buffer = payload.data();
  tile.data._length = tile.data._maximum = static_cast<uint32_t>(payload.size());
  tile.data._release = false;
  ASSERT_TRUE(writer.Write(tile).ok());
  std::vector<uint8_t> received;
  ASSERT_TRUE(Eventually([&] {
    (void)reader.Take([&](const fleetloc_Tile& t, const dds_sample_info_t&) {
      received.assign(t.data._buffer, t.data._buffer + t.data._length);
    });
    return !received.empty();
  }));
  EXPECT_EQ(received, payload);
}

TEST(Transport, PartitionsKeepRepliesToTheirVehicle) {
  Participant server = Unwrap(Participant::Create(kDomain));
  Participant vehicle = Unwrap(Participant::Create(kDomain));
  auto topic_s = Unwrap(Topic<fleetloc_PatchAck>::Create(server, "test_ack"));
  auto topic_v = Unwrap(Topic<fleetloc_PatchAck>::Create(vehicle, "test_ack"));
  Entity pub_a = Unwrap(server.CreatePublisher({"vehicle/a"}));
  Entity sub_a = Unwrap(vehicle.CreateSubscriber({"vehicle/a"}));
  Entity sub_b = Unwrap(vehicle.CreateSubscriber({"vehicle/b"}));
  auto writer = Unwrap(Writer<fleetloc_PatchAck>::Create(pub_a.get(), topic_s, CommandQos()));
  auto reader_a = Unwrap(Reader<fleetloc_PatchAck>::Create(sub_a.get(), topic_v, CommandQos()));
  auto reader_b = Unwrap(Reader<fleetloc_PatchAck>::Create(sub_b.get(), topic_v, CommandQos()));
  ASSERT_TRUE(Eventually([&] { return writer.MatchedReaders() == 1; }));
  EXPECT_EQ(reader_b.MatchedWriters(), 0);
  fleetloc_PatchAck ack{};
  std::snprintf(ack.vehicle_id, sizeof ack.vehicle_id, "a");
  ack.sequence_number = 42;
  ASSERT_TRUE(writer.Write(ack).ok());
  int at_a = 0, at_b = 0;
  ASSERT_TRUE(Eventually([&] {
    (void)reader_a.Take([&](const fleetloc_PatchAck&, const dds_sample_info_t&) { ++at_a; });
    return at_a == 1;
  }));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  (void)reader_b.Take([&](const fleetloc_PatchAck&, const dds_sample_info_t&) { ++at_b; });
  EXPECT_EQ(at_b, 0);
}

TEST(Transport, LateJoinerGetsDurableState) {
  Participant server = Unwrap(Participant::Create(kDomain));
  auto topic_s = Unwrap(Topic<fleetloc_MosaicInfo>::Create(server, "test_info"));
  auto writer =
      Unwrap(Writer<fleetloc_MosaicInfo>::Create(server.get(), topic_s, DurableStateQos()));
  fleetloc_MosaicInfo info{};
  std::snprintf(info.server_id, sizeof info.server_id, "map-1");
  info.version = 7;
  ASSERT_TRUE(writer.Write(info).ok());
  Participant late = Unwrap(Participant::Create(kDomain));
  auto topic_l = Unwrap(Topic<fleetloc_MosaicInfo>::Create(late, "test_info"));
  auto reader = Unwrap(Reader<fleetloc_MosaicInfo>::Create(late.get(), topic_l, DurableStateQos()));
  WaitSet waitset = Unwrap(WaitSet::Create(late));
  ASSERT_TRUE(waitset.AttachReader(reader.get(), 5).ok());
  long long version = 0;
  ASSERT_TRUE(Eventually([&] {
    auto tags = waitset.Wait(0.1);
    EXPECT_TRUE(tags.ok());
    (void)reader.Take(
        [&](const fleetloc_MosaicInfo& i, const dds_sample_info_t&) { version = i.version; });
    return version == 7;
  }));
}

TEST(Transport, WakeReturnsWaitAtOnce) {
  Participant p = Unwrap(Participant::Create(kDomain));
  WaitSet waitset = Unwrap(WaitSet::Create(p));
  ASSERT_TRUE(waitset.Wake().ok());
  const auto start = std::chrono::steady_clock::now();
  auto tags = waitset.Wait(30.0);
  ASSERT_TRUE(tags.ok());
  EXPECT_TRUE(tags->empty());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST(Transport, MalformedConfigurationIsAnErrorNamingTheDomain) {
  Result<Participant> p =
      Participant::Create(72, DdsConfig{"<CycloneDDS><Domain><Bogus/></Domain>", ""});
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("domain 72"), std::string::npos) << p.status().message();
}

TEST(Transport, MissingConfigurationFileIsNotFound) {
  Result<Participant> p = Participant::Create(73, DdsConfig{"", "/nonexistent/cyclone.xml"});
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.status().code(), StatusCode::kNotFound);
  EXPECT_NE(p.status().message().find("/nonexistent/cyclone.xml"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::transport
