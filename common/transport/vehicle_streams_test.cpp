// Vehicle streams: the partition check alone, then through DDS (a forged vehicle_id written in
// another vehicle's partition is rejected and counted, the honest sample is delivered).
#include "transport/vehicle_streams.h"

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <thread>

#include "base/eventually.h"
#include "transport/topic_names.h"

namespace fleetloc::transport {
namespace {

constexpr uint32_t kDomain = 110;  // this test binary's own domain

TEST(CheckVehiclePartition, AcceptsExactlyTheVehiclesOwnPartition) {
  EXPECT_TRUE(CheckVehiclePartition("agv-1", {"fleetloc.vehicle.agv-1"}).ok());
}

TEST(CheckVehiclePartition, RejectsAnotherVehiclesPartitionNamingBoth) {
  const Status s = CheckVehiclePartition("agv-2", {"fleetloc.vehicle.agv-1"});
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("'agv-2'"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("'fleetloc.vehicle.agv-1'"), std::string::npos) << s.message();
}

TEST(CheckVehiclePartition, RejectsDefaultWildcardAndExtraPartitions) {
  EXPECT_FALSE(CheckVehiclePartition("agv-1", {}).ok());
  EXPECT_FALSE(CheckVehiclePartition("agv-1", {"fleetloc.vehicle.*"}).ok());
  EXPECT_FALSE(
      CheckVehiclePartition("agv-1", {"fleetloc.vehicle.agv-1", "fleetloc.vehicle.agv-2"}).ok());
  EXPECT_FALSE(CheckVehiclePartition("agv-1", {"fleetloc.vehicle.agv-10"}).ok());
}

using testing::Eventually;

fleetloc_VehiclePose Pose(const char* vehicle_id, double x) {
  fleetloc_VehiclePose pose{};
  pose.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  std::snprintf(pose.vehicle_id, sizeof pose.vehicle_id, "%s", vehicle_id);
  pose.x = x;
  return pose;
}

TEST(VehicleStreamReader, DeliversOwnVehicleIdAndRejectsAForgedOneWrittenInAnotherPartition) {
  Participant vehicle = Participant::Create(kDomain).value();
  Participant receiver = Participant::Create(kDomain).value();
  auto topic_v = Topic<fleetloc_VehiclePose>::Create(vehicle, topics::kVehiclePose).value();
  auto topic_r = Topic<fleetloc_VehiclePose>::Create(receiver, topics::kVehiclePose).value();
  Entity publisher = CreateVehiclePublisher(vehicle, "agv-1").value();
  auto writer =
      Writer<fleetloc_VehiclePose>::Create(publisher.get(), topic_v, CommandQos()).value();
  auto outside = Writer<fleetloc_VehiclePose>::Create(vehicle.get(), topic_v, CommandQos()).value();
  auto reader =
      VehicleStreamReader<fleetloc_VehiclePose>::Create(receiver, topic_r, CommandQos()).value();
  ASSERT_TRUE(Eventually([&] { return writer.MatchedReaders() == 1; }));
  EXPECT_EQ(outside.MatchedReaders(), 0);  // the default partition is not a vehicle's
  ASSERT_TRUE(writer.Write(Pose("agv-2", 2.0)).ok());
  ASSERT_TRUE(writer.Write(Pose("agv-1", 1.0)).ok());
  std::vector<double> delivered;
  std::vector<std::string> rejections;
  ASSERT_TRUE(Eventually([&] {
    (void)reader.TakeAll(
        [&](const fleetloc_VehiclePose& p, const dds_sample_info_t&) { delivered.push_back(p.x); },
        [&](const std::string& message) { rejections.push_back(message); });
    return delivered.size() + rejections.size() >= 2;
  }));
  EXPECT_EQ(delivered, std::vector<double>{1.0});
  ASSERT_EQ(rejections.size(), 1u);
  EXPECT_NE(rejections[0].find("'agv-2' written in 'fleetloc.vehicle.agv-1'"), std::string::npos)
      << rejections[0];
  EXPECT_EQ(reader.rejected(), 1u);
}

TEST(VehicleStreamReader, ChecksTheSamplesOfAWriterThatIsGoneBeforeTheyAreTaken) {
  Participant vehicle = Participant::Create(kDomain).value();
  Participant receiver = Participant::Create(kDomain).value();
  auto topic_v = Topic<fleetloc_VehiclePose>::Create(vehicle, topics::kVehiclePose).value();
  auto topic_r = Topic<fleetloc_VehiclePose>::Create(receiver, topics::kVehiclePose).value();
  auto reader =
      VehicleStreamReader<fleetloc_VehiclePose>::Create(receiver, topic_r, CommandQos()).value();
  {
    auto writer =
        VehicleStreamWriter<fleetloc_VehiclePose>::Create(vehicle, "agv-3", topic_v, CommandQos())
            .value();
    ASSERT_TRUE(
        Eventually([&] { return writer.MatchedReaders() == 1 && reader.MatchedWriters() == 1; }));
    int none = 0;
    (void)reader.TakeAll(
        [&](const fleetloc_VehiclePose&, const dds_sample_info_t&) { ++none; });  // learns it
    EXPECT_EQ(none, 0);
    ASSERT_TRUE(writer.Write(Pose("agv-3", 3.0)).ok());
    ASSERT_TRUE(writer.Write(Pose("agv-4", 4.0)).ok());
    ASSERT_TRUE(Eventually([&] {  // both arrived (dds_read leaves them to take)
      void* samples[4] = {};
      dds_sample_info_t infos[4];
      const dds_return_t n = dds_read(reader.get(), samples, infos, 4, 4);
      if (n > 0) dds_return_loan(reader.get(), samples, n);
      return n == 2;
    }));
  }  // the writer is deleted here
  ASSERT_TRUE(Eventually([&] { return reader.MatchedWriters() == 0; }));
  std::vector<double> delivered;
  int rejected = 0;
  (void)reader.TakeAll(
      [&](const fleetloc_VehiclePose& p, const dds_sample_info_t&) { delivered.push_back(p.x); },
      [&](const std::string&) { ++rejected; });
  EXPECT_EQ(delivered, std::vector<double>{3.0});
  EXPECT_EQ(rejected, 1);
}

}  // namespace
}  // namespace fleetloc::transport
