// PatchObservation → PatchStore → PatchAck.
#include "map_server/patch_service.h"

#include <spdlog/spdlog.h>

#include "transport/wire_util.h"

namespace fleetloc::map_server {

std::vector<std::string> PatchService::CounterNames() {
  return {"patches_received",        "patches_stored",          "patches_duplicate",
          "rejected_patch_malformed", "rejected_patch_oversized", "rejected_patch_image",
          "rejected_patch_mosaic",   "patch_store_errors",      "patch_acks_unmatched"};
}

PatchService::PatchService(mosaic::PatchStore* patches, mosaic::TileStore* tiles,
                           PatchLimits limits, VehicleChannels* channels,
                           ServerCounters* counters)
    : patches_(patches), tiles_(tiles), limits_(limits), channels_(channels), counters_(counters) {}

void PatchService::Receive(const fleetloc_PatchObservation& sample) {
  counters_->Add("patches_received");
  const std::string vehicle = transport::GetBounded(sample.vehicle_id);
  DecodedPatch decoded = DecodePatch(sample, tiles_->layout(), limits_);
  if (!decoded.record.ok()) {
    counters_->Reject(decoded.reject_counter, decoded.record.status().message());
    // Without a valid id there is no partition to answer in.
    if (transport::IsValidEntityId(vehicle)) {
      acks_.Push(vehicle, {sample.sequence_number, fleetloc_PATCH_REJECTED,
                           decoded.record.status().message()});
    }
    return;
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
