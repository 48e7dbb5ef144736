// Collects PatchObservations: each is checked and decoded, stored in one SQLite transaction
// (idempotent on vehicle and sequence number), then acknowledged in the vehicle's partition.
// A quarantined vehicle's patches (mosaic/vehicle_standing_store.h) are refused on arrival.
// A rejected patch is acknowledged as rejected with the reason (retrying cannot help); a patch
// that could not be stored (SQLite failure) is not acknowledged, so the vehicle retries it and
// nothing acknowledged is ever lost.
#pragma once

#include <string>
#include <vector>

#include "map_server/patch_decoder.h"
#include "map_server/pending_replies.h"
#include "map_server/server_counters.h"
#include "map_server/vehicle_channels.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_store.h"
#include "mosaic/vehicle_standing_store.h"

namespace fleetloc::map_server {

class PatchService {
 public:
  static std::vector<std::string> CounterNames();

  PatchService(mosaic::PatchStore* patches, mosaic::TileStore* tiles,
               mosaic::VehicleStandingStore* standing, PatchLimits limits,
               VehicleChannels* channels, ServerCounters* counters);

  void Receive(const fleetloc_PatchObservation& sample);
  // Sends the acknowledgements whose vehicle's reader is matched.
  void FlushAcks(std::chrono::steady_clock::duration match_timeout = std::chrono::seconds(5));

 private:
  struct Ack {
    uint64_t sequence = 0;
    fleetloc_PatchAckStatus status = fleetloc_PATCH_REJECTED;
    std::string reason;
  };
  // Counts a rejection and queues its acknowledgement (when the id can be answered at all).
  void Refuse(const std::string& vehicle, uint64_t sequence, const std::string& counter,
              const std::string& reason);

  mosaic::PatchStore* patches_;
  mosaic::TileStore* tiles_;
  mosaic::VehicleStandingStore* standing_;
  PatchLimits limits_;
  VehicleChannels* channels_;
  ServerCounters* counters_;
  PendingReplies<Ack> acks_;
};

}  // namespace fleetloc::map_server
