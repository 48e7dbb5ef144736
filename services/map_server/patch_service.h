// Collects PatchObservations. On the DDS loop only what is cheap: the patch's fields and its
// PNG header are checked, then its vehicle's budget (patch_budget.h: rate and quota) — a patch over
// budget, or one that finds the decoding queue full, is not acknowledged and comes again later.
// A thread of its own then refuses a quarantined vehicle's patch (mosaic/vehicle_standing_store.h),
// decodes the image (a corrupt one is refused) and stores the PNG as received in one SQLite
// transaction (idempotent on vehicle and sequence number); the acknowledgement goes out from the
// DDS loop in the vehicle's partition. So a flood of patches never holds up the tiles.
// A rejected patch is acknowledged as rejected with the reason (retrying cannot help); a patch that
// could not be stored (SQLite failure) is not acknowledged, so the vehicle retries it and nothing
// acknowledged is ever lost.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "map_server/patch_budget.h"
#include "map_server/patch_decoder.h"
#include "map_server/pending_replies.h"
#include "map_server/server_counters.h"
#include "map_server/vehicle_channels.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_store.h"
#include "mosaic_upkeep/vehicle_standing_store.h"
#include "transport/patch_messages.h"

namespace fleetloc::map_server {

struct PatchIntake {
  PatchLimits limits;
  PatchBudgetOptions budget;
  int queue = 16;          // checked patches waiting to be decoded and stored
  int max_queued_mb = 64;  // their bytes together
};

class PatchService {
 public:
  static std::vector<std::string> CounterNames();

  // `store` is read on the DDS thread only (the served layout); the other stores are used by the
  // service's thread.
  PatchService(mosaic::PatchStore* patches, mosaic::TileStore* tiles,
               mosaic_upkeep::VehicleStandingStore* standing, PatchIntake intake,
               VehicleChannels* channels, ServerCounters* counters);
  ~PatchService();  // finishes the patch being stored, drops the queued ones (not acknowledged)

  void Receive(const fleetloc_PatchObservation& sample);
  // Sends the acknowledgements whose vehicle's reader is matched.
  void FlushAcks(std::chrono::steady_clock::duration match_timeout = std::chrono::seconds(5));
  // Re-reads every vehicle's stored patches into the budget (after re-maps and prunes).
  void RefreshUsage();
  // Patches checked and waiting for the service's thread.
  size_t queued() const;

 private:
  using Ack = transport::PatchAckReply;
  void Work();
  void Store(mosaic::PatchRecord& record);
  // Counts a rejection and queues its acknowledgement (when the id can be answered at all).
  void Refuse(const std::string& vehicle, uint64_t sequence, const std::string& counter,
              const std::string& reason);
  void PushAck(const std::string& vehicle, Ack ack);

  mosaic::PatchStore* patches_;
  mosaic::TileStore* tiles_;
  mosaic_upkeep::VehicleStandingStore* standing_;
  const PatchIntake intake_;
  PatchBudget budget_;
  VehicleChannels* channels_;
  ServerCounters* counters_;
  std::mutex ack_mutex_;
  PendingReplies<Ack> acks_;
  mutable std::mutex queue_mutex_;
  std::condition_variable wake_;
  std::deque<mosaic::PatchRecord> queue_;
  size_t queued_bytes_ = 0;
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace fleetloc::map_server
