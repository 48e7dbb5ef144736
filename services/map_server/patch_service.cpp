// PatchObservation → checks and budget (DDS loop) → decode and PatchStore (own thread) → PatchAck.
#include "map_server/patch_service.h"

#include <spdlog/spdlog.h>

#include "transport/wire_util.h"

namespace fleetloc::map_server {
namespace {

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string Name(const mosaic::PatchRecord& r) {
  return "PatchObservation " + r.vehicle_id + "#" + std::to_string(r.sequence);
}

}  // namespace

std::vector<std::string> PatchService::CounterNames() {
  return {"patches_received",
          "patches_stored",
          "patches_duplicate",
          "rejected_patch_malformed",
          "rejected_patch_oversized",
          "rejected_patch_image",
          "rejected_patch_mosaic",
          "patch_store_errors",
          "patch_acks_unmatched",
          "rejected_patch_covariance",
          "rejected_patch_quarantined",
          BudgetVerdictName(BudgetVerdict::kRateLimited),
          BudgetVerdictName(BudgetVerdict::kOverVehicleQuota),
          BudgetVerdictName(BudgetVerdict::kOverTotalQuota),
          "patches_deferred"};
}

PatchService::PatchService(mosaic::PatchStore* patches, mosaic::TileStore* tiles,
                           mosaic_upkeep::VehicleStandingStore* standing, PatchIntake intake,
                           VehicleChannels* channels, ServerCounters* counters)
    : patches_(patches),
      tiles_(tiles),
      standing_(standing),
      intake_(intake),
      budget_(intake.budget),
      channels_(channels),
      counters_(counters) {
  RefreshUsage();
  worker_ = std::thread([this] { Work(); });
}

PatchService::~PatchService() {
  {
    std::lock_guard lock(queue_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void PatchService::RefreshUsage() {
  Result<std::map<std::string, mosaic::StoredUsage>> stored = patches_->UsageByVehicle();
  if (!stored.ok()) return spdlog::warn("patch quotas: {}", stored.status().message());
  std::map<std::string, PatchUsage> usage;
  for (const auto& [vehicle, u] : *stored) usage[vehicle] = {u.patches, u.bytes};
  budget_.SetUsage(std::move(usage));
}

size_t PatchService::queued() const {
  std::lock_guard lock(queue_mutex_);
  return queue_.size();
}

void PatchService::Refuse(const std::string& vehicle, uint64_t sequence, const std::string& counter,
                          const std::string& reason) {
  counters_->Reject(counter, reason);
  // Without a valid id there is no partition to answer in.
  if (transport::IsValidEntityId(vehicle))
    PushAck(vehicle, {sequence, fleetloc_PATCH_REJECTED, reason});
}

void PatchService::PushAck(const std::string& vehicle, Ack ack) {
  std::lock_guard lock(ack_mutex_);
  acks_.Push(vehicle, std::move(ack));
}

void PatchService::Receive(const fleetloc_PatchObservation& sample) {
  counters_->Add("patches_received");
  const std::string vehicle = transport::GetBounded(sample.vehicle_id);
  DecodedPatch checked = CheckPatch(sample, tiles_->layout(), intake_.limits);
  if (!checked.record.ok()) {
    return Refuse(vehicle, sample.sequence_number, checked.reject_counter,
                  checked.record.status().message());
  }
  mosaic::PatchRecord& record = *checked.record;
  const auto bytes = static_cast<long long>(transport::OctetSpan(sample.image).size());
  // Over budget or no room to queue: not acknowledged, the vehicle sends it again later (and its
  // bytes are not even copied).
  const BudgetVerdict verdict = budget_.Admit(vehicle, bytes, SteadySeconds());
  if (verdict != BudgetVerdict::kAccept) return counters_->Add(BudgetVerdictName(verdict));
  {
    std::lock_guard lock(queue_mutex_);
    const size_t max_bytes = static_cast<size_t>(intake_.max_queued_mb) << 20;
    if (queue_.size() < static_cast<size_t>(intake_.queue) &&
        queued_bytes_ + static_cast<size_t>(bytes) <= max_bytes) {
      transport::CopyPng(sample, &record);
      queued_bytes_ += record.png.size();
      queue_.push_back(std::move(record));
      wake_.notify_one();
      return;
    }
  }
  budget_.Unreserve(vehicle, bytes);
  counters_->Add("patches_deferred");
}

void PatchService::Work() {
  for (;;) {
    mosaic::PatchRecord record;
    {
      std::unique_lock lock(queue_mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      record = std::move(queue_.front());
      queue_.pop_front();
      queued_bytes_ -= record.png.size();
    }
    Store(record);
  }
}

void PatchService::Store(mosaic::PatchRecord& record) {
  const long long bytes = static_cast<long long>(record.png.size());
  const auto sequence = static_cast<uint64_t>(record.sequence);
  Result<bool> quarantined = standing_->IsQuarantined(record.vehicle_id);
  if (quarantined.ok() && *quarantined) {
    budget_.Unreserve(record.vehicle_id, bytes);
    return Refuse(record.vehicle_id, sequence, "rejected_patch_quarantined",
                  Name(record) +
                      ": vehicle quarantined (its patches kept failing admission; "
                      "fleetctl mosaic vehicles --release lifts it)");
  }
  if (Status decoded = DecodePatchImage(&record, intake_.limits); !decoded.ok()) {
    budget_.Unreserve(record.vehicle_id, bytes);
    return Refuse(record.vehicle_id, sequence, "rejected_patch_image", decoded.message());
  }
  Result<mosaic::PutOutcome> stored = patches_->Put(record);
  if (!stored.ok()) {
    budget_.Unreserve(record.vehicle_id, bytes);
    counters_->Reject("patch_store_errors", stored.status().message());
    return;  // not acknowledged: the vehicle keeps it in its outbox and retries
  }
  const bool duplicate = *stored == mosaic::PutOutcome::kDuplicate;
  if (duplicate) {
    budget_.Unreserve(record.vehicle_id, bytes);
  } else {
    budget_.Commit(record.vehicle_id, bytes);
  }
  counters_->Add(duplicate ? "patches_duplicate" : "patches_stored");
  PushAck(record.vehicle_id,
          {sequence, duplicate ? fleetloc_PATCH_DUPLICATE : fleetloc_PATCH_STORED, ""});
}

void PatchService::FlushAcks(std::chrono::steady_clock::duration match_timeout) {
  std::lock_guard lock(ack_mutex_);
  acks_.Flush(
      [&](const std::string& vehicle) {
        Result<VehicleChannel*> channel = channels_->Get(vehicle);
        return channel.ok() && (*channel)->acks.MatchedReaders() > 0;
      },
      [&](const std::string& vehicle, const Ack& ack) {
        Result<VehicleChannel*> channel = channels_->Get(vehicle);
        if (Status sent = (*channel)->acks.Write(transport::ToIdl(ack, vehicle)); !sent.ok()) {
          counters_->Reject("patch_store_errors", sent.message());
        }
      },
      [&](const std::string& vehicle, const Ack& ack) {
        // The patch is stored; the vehicle will resend it and get a duplicate acknowledgement.
        counters_->Add("patch_acks_unmatched");
        spdlog::warn("PatchAck {}#{}: no ack reader of that vehicle matched", vehicle,
                     ack.sequence);
      },
      match_timeout);
}

}  // namespace fleetloc::map_server
