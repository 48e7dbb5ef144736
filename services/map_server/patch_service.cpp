// PatchObservation → PatchStore → PatchAck.
#include "map_server/patch_service.h"

#include <spdlog/spdlog.h>

#include "transport/wire_util.h"

namespace fleetloc::map_server {

std::vector<std::string> PatchService::CounterNames() {
  return {"patches_received",        "patches_stored",          "patches_duplicate",
          "rejected_patch_malformed", "rejected_patch_oversized", "rejected_patch_image",
          "rejected_patch_mosaic",   "patch_store_errors",      "patch_acks_unmatched",
          "rejected_patch_covariance", "rejected_patch_quarantined"};
}

PatchService::PatchService(mosaic::PatchStore* patches, mosaic::TileStore* tiles,
                           mosaic::VehicleStandingStore* standing, PatchLimits limits,
                           VehicleChannels* channels, ServerCounters* counters)
    : patches_(patches),
      tiles_(tiles),
      standing_(standing),
      limits_(limits),
      channels_(channels),
      counters_(counters) {}

void PatchService::Refuse(const std::string& vehicle, uint64_t sequence, const std::string& counter,
                          const std::string& reason) {
  counters_->Reject(counter, reason);
  // Without a valid id there is no partition to answer in.
  if (transport::IsValidEntityId(vehicle)) {
    acks_.Push(vehicle, {sequence, fleetloc_PATCH_REJECTED, reason});
  }
}

void PatchService::Receive(const fleetloc_PatchObservation& sample) {
  counters_->Add("patches_received");
  const std::string vehicle = transport::GetBounded(sample.vehicle_id);
  if (transport::IsValidEntityId(vehicle)) {
    Result<bool> quarantined = standing_->IsQuarantined(vehicle);
    if (quarantined.ok() && *quarantined) {
      return Refuse(vehicle, sample.sequence_number, "rejected_patch_quarantined",
                    "PatchObservation " + vehicle + "#" + std::to_string(sample.sequence_number) +
                        ": vehicle quarantined (its patches kept failing admission; "
                        "fleetctl mosaic vehicles --release lifts it)");
    }
  }
  DecodedPatch decoded = DecodePatch(sample, tiles_->layout(), limits_);
  if (!decoded.record.ok()) {
    return Refuse(vehicle, sample.sequence_number, decoded.reject_counter,
                  decoded.record.status().message());
  }
  Result<mosaic::PutOutcome> stored = patches_->Put(*decoded.record);
  if (!stored.ok()) {
    counters_->Reject("patch_store_errors", stored.status().message());
    return;  // not acknowledged: the vehicle keeps it in its outbox and retries
  }
  const bool duplicate = *stored == mosaic::PutOutcome::kDuplicate;
  counters_->Add(duplicate ? "patches_duplicate" : "patches_stored");
  acks_.Push(vehicle, {sample.sequence_number,
                       duplicate ? fleetloc_PATCH_DUPLICATE : fleetloc_PATCH_STORED, ""});
}

void PatchService::FlushAcks(std::chrono::steady_clock::duration match_timeout) {
  acks_.Flush(
      [&](const std::string& vehicle) {
        Result<VehicleChannel*> channel = channels_->Get(vehicle);
        return channel.ok() && (*channel)->acks.MatchedReaders() > 0;
      },
      [&](const std::string& vehicle, const Ack& ack) {
        fleetloc_PatchAck message{};
        message.wire_version = fleetloc_WIRE_VERSION;
        transport::SetBounded(message.vehicle_id, vehicle);
        message.sequence_number = ack.sequence;
        message.status = ack.status;
        transport::SetBounded(message.reason, ack.reason);
        Result<VehicleChannel*> channel = channels_->Get(vehicle);
        if (Status sent = (*channel)->acks.Write(message); !sent.ok()) {
          counters_->Reject("patch_store_errors", sent.message());
        }
      },
      [&](const std::string& vehicle, const Ack& ack) {
        // The patch is stored; the vehicle will resend it and get a duplicate acknowledgement.
        counters_->Add("patch_acks_unmatched");
        spdlog::warn("PatchAck {}#{}: no ack reader of that vehicle matched", vehicle, ack.sequence);
      },
      match_timeout);
}

}  // namespace fleetloc::map_server
