// security_probe: one DDS participant with a given Cyclone configuration (a secured one from
// deploy/security/make_security.sh, a forged one, or none) that tries what a vehicle or an
// intruder would, for tests/security_test.cpp. It prints one line per attempt:
//   security_probe --domain D [--dds-config FILE] --remap
//       tries to create a RemapCommand writer (transport::RemapClient);
//   security_probe --domain D [--dds-config FILE] --partition-of V --vehicle-id ID [--seconds S]
//       creates VehiclePose, VehicleHealth and PatchObservation writers in vehicle V's partition
//       and for S seconds (default 4) writes samples naming vehicle ID at 10 Hz; then prints the
//       largest number of readers its pose writer matched.
// Exit status: 0 when every writer was created, 3 when one was refused, 2 on bad arguments.
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <thread>

#include "transport/remap_client.h"
#include "transport/topic_names.h"
#include "transport/vehicle_streams.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

// Returns false (after printing why) when the writer could not be created.
template <typename T>
bool Report(const char* what, const Result<T>& created) {
  std::printf("%s writer: %s\n", what, created.ok() ? "ok" : created.status().message().c_str());
  return created.ok();
}

int TryRemap(const Participant& participant) {
  return Report("remap_command", RemapClient::Create(participant)) ? 0 : 3;
}

template <typename T>
Result<VehicleStreamWriter<T>> Open(const Participant& p, const std::string& partition_of,
                                    const char* topic_name, const Qos& qos) {
  auto topic = Topic<T>::Create(p, topic_name);
  if (!topic.ok()) return topic.status();
  return VehicleStreamWriter<T>::Create(p, partition_of, *topic, qos);
}

int WriteStreams(const Participant& p, const std::string& partition_of, const std::string& id,
                 double seconds) {
  auto poses = Open<fleetloc_VehiclePose>(p, partition_of, topics::kVehiclePose, PoseStreamQos());
  auto health =
      Open<fleetloc_VehicleHealth>(p, partition_of, topics::kVehicleHealth, PeriodicStateQos(3, 5));
  auto patches =
      Open<fleetloc_PatchObservation>(p, partition_of, topics::kPatchObservation, BulkQos(64, 0.1));
  const bool all = Report("vehicle_pose", poses) & Report("vehicle_health", health) &
                   Report("patch_observation", patches);
  int matched = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (uint32_t n = 1; std::chrono::steady_clock::now() < end; ++n) {
    if (poses.ok()) {
      fleetloc_VehiclePose pose{};
      pose.wire_version = fleetloc_CURRENT_WIRE_VERSION;
      SetBounded(pose.vehicle_id, id);
      pose.stamp = NowStamp();
      pose.x = n;
      pose.covariance[0] = pose.covariance[4] = pose.covariance[8] = 1e-6;
      (void)poses->Write(pose);
      matched = std::max(matched, poses->MatchedReaders());
    }
    if (health.ok()) {
      fleetloc_VehicleHealth h{};
      h.wire_version = fleetloc_CURRENT_WIRE_VERSION;
      SetBounded(h.vehicle_id, id);
      h.stamp = NowStamp();
      (void)health->Write(h);
    }
    if (patches.ok() && n % 10 == 1) {  // not a valid patch: a receiver must reject it unread
      fleetloc_PatchObservation patch{};
      patch.wire_version = fleetloc_CURRENT_WIRE_VERSION;
      SetBounded(patch.vehicle_id, id);
      patch.sequence_number = n;
      (void)patches->Write(patch);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::printf("matched pose readers: %d\n", matched);
  return all ? 0 : 3;
}

int Main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--remap") {
      args[key] = "yes";
    } else if (i + 1 < argc) {
      args[key] = argv[++i];
    } else {
      std::fprintf(stderr, "security_probe: %s needs a value\n", key.c_str());
      return 2;
    }
  }
  if (!args.count("--domain") ||
      args["--domain"].find_first_not_of("0123456789") != std::string::npos) {
    std::fprintf(stderr, "security_probe: --domain N is required\n");
    return 2;
  }
  auto participant = Participant::Create(std::stoul(args["--domain"]), {"", args["--dds-config"]});
  if (!participant.ok()) {
    std::printf("participant: %s\n", participant.status().message().c_str());
    return 3;
  }
  std::fflush(stdout);
  if (args.count("--remap")) return TryRemap(*participant);
  const double seconds = args.count("--seconds") ? std::stod(args["--seconds"]) : 4.0;
  return WriteStreams(*participant, args["--partition-of"], args["--vehicle-id"], seconds);
}

}  // namespace
}  // namespace fleetloc::transport

int main(int argc, char** argv) { return fleetloc::transport::Main(argc, argv); }
