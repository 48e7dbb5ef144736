// The vehicle side of patch collection: sends PatchObservations and takes the map server's
// PatchAcks from the vehicle's own partition. The agent's outbox (retry until acknowledged) is
// built on it; tests and tools use it directly.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "transport/matched_writers.h"
#include "transport/patch_messages.h"
#include "transport/typed_io.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::transport {

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
