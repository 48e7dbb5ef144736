// The vehicle side of patch collection: sends PatchObservations and takes the map server's
// PatchAcks from the vehicle's own partition. The agent's outbox (retry until acknowledged) is
// built on it; tests and tools use it directly.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "geometry/pose2.h"
#include "transport/matched_writers.h"
#include "transport/typed_io.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::transport {

// What a vehicle reports of one floor patch (see PatchObservation in idl/fleetloc.idl).
struct PatchToSend {
  uint64_t sequence = 0;
  double stamp_s = 0;
  std::string mosaic_id;
  long long mosaic_version = 0;
  geometry::Pose2 pose;       // camera_ground of the image centre in map
  double covariance[9] = {};  // row-major (x, y, theta)
  float quality = 0;
  double resolution_m = 0;
  std::vector<std::uint8_t> png;  // 8-bit gray PNG
};

struct ReceivedAck {
  uint64_t sequence = 0;
  std::string server_id;  // the acknowledging map server; empty when its writer does not say
  fleetloc_PatchAckStatus status = fleetloc_PATCH_REJECTED;
  std::string reason;
};

class PatchClient {
 public:
  static Result<std::unique_ptr<PatchClient>> Create(const Participant& participant,
                                                     const std::string& vehicle_id);
  Status Send(const PatchToSend& patch);
  // Sends an already filled wire sample as is (tests use it to forge bad ones).
  Status SendRaw(const fleetloc_PatchObservation& sample);
  // The acknowledgements received so far, each with the map server that wrote it.
  Result<std::vector<ReceivedAck>> TakeAcks();
  bool ServerMatched() const { return patches_.MatchedReaders() > 0; }
  dds_entity_t ack_reader() const { return ack_reader_.get(); }

 private:
  PatchClient(std::string vehicle_id, Entity subscriber,
              Topic<fleetloc_PatchObservation> patch_topic, Topic<fleetloc_PatchAck> ack_topic,
              VehicleStreamWriter<fleetloc_PatchObservation> patches,
              Reader<fleetloc_PatchAck> ack_reader);
  std::string vehicle_id_;
  Entity subscriber_;
  Topic<fleetloc_PatchObservation> patch_topic_;
  Topic<fleetloc_PatchAck> ack_topic_;
  VehicleStreamWriter<fleetloc_PatchObservation> patches_;  // in the vehicle's partition
  Reader<fleetloc_PatchAck> ack_reader_;
  MatchedWriters ack_writers_{ack_reader_.get()};  // which server wrote an ack
};

}  // namespace fleetloc::transport
