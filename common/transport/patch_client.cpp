// PatchObservation writer and partitioned PatchAck reader, vehicle side.
#include "transport/patch_client.h"

#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {

PatchClient::PatchClient(std::string vehicle_id, Entity subscriber,
                         Topic<fleetloc_PatchObservation> patch_topic,
                         Topic<fleetloc_PatchAck> ack_topic,
                         VehicleStreamWriter<fleetloc_PatchObservation> patches,
                         Reader<fleetloc_PatchAck> ack_reader)
    : vehicle_id_(std::move(vehicle_id)),
      subscriber_(std::move(subscriber)),
      patch_topic_(std::move(patch_topic)),
      ack_topic_(std::move(ack_topic)),
      patches_(std::move(patches)),
      ack_reader_(std::move(ack_reader)) {}

Result<std::unique_ptr<PatchClient>> PatchClient::Create(const Participant& participant,
                                                         const std::string& vehicle_id) {
  if (!IsValidEntityId(vehicle_id)) {
    return InvalidInput("vehicle id '" + vehicle_id + "' is not 1-11 of [A-Za-z0-9_-]");
  }
  auto patch_topic =
      Topic<fleetloc_PatchObservation>::Create(participant, topics::kPatchObservation);
  auto ack_topic = Topic<fleetloc_PatchAck>::Create(participant, topics::kPatchAck);
  if (!patch_topic.ok()) return patch_topic.status();
  if (!ack_topic.ok()) return ack_topic.status();
  auto subscriber = participant.CreateSubscriber({topics::VehiclePartition(vehicle_id)});
  if (!subscriber.ok()) return subscriber.status();
  // A vehicle never stalls on a patch: a write with no room within 0.1 s fails, and the patch
  // stays in the caller's outbox for a later retry.
  auto patches = VehicleStreamWriter<fleetloc_PatchObservation>::Create(
      participant, vehicle_id, *patch_topic, BulkQos(64, 0.1));
  auto acks = Reader<fleetloc_PatchAck>::Create(subscriber->get(), *ack_topic, CommandQos());
  if (!patches.ok()) return patches.status();
  if (!acks.ok()) return acks.status();
  return std::unique_ptr<PatchClient>(new PatchClient(
      vehicle_id, std::move(subscriber).value(), std::move(patch_topic).value(),
      std::move(ack_topic).value(), std::move(patches).value(), std::move(acks).value()));
}

Status PatchClient::Send(const PatchToSend& p) {
  const fleetloc_PatchObservation sample = ToIdl(p, vehicle_id_);
  return SendRaw(sample);
}

Status PatchClient::SendRaw(const fleetloc_PatchObservation& sample) {
  return patches_.Write(sample);
}

Result<std::vector<ReceivedAck>> PatchClient::TakeAcks() {
  std::vector<ReceivedAck> acks;
  ack_writers_.LearnNew();
  Result<int> taken =
      ack_reader_.TakeAll([&](const fleetloc_PatchAck& a, const dds_sample_info_t& info) {
        const WriterFacts* writer = ack_writers_.Find(info.publication_handle);
        acks.push_back(
            FromIdl(a, writer ? topics::ServerIdFromUserData(writer->user_data) : std::string()));
      });
  if (!taken.ok()) return taken.status();
  return acks;
}

}  // namespace fleetloc::transport
