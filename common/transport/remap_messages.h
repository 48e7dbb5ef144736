// Re-mapping on the wire (RemapCommand, RemapStatus) as plain values, and the one place they are
// converted: the maintainer's client (remap_client.h) and the map server's remap service both call
// these.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "transport/fleetloc_types.h"

namespace fleetloc::transport {

struct RemapRequest {
  double x_min = 0, y_min = 0, x_max = 0, y_max = 0;  // map metres
  bool replace = false;                               // else blend
  std::string mosaic_id;                              // empty: the one the server serves
  std::string requester;                              // at most 31 characters
};

// One RemapStatus as plain values.
struct RemapProgress {
  uint64_t command_id = 0;
  std::string server_id;
  fleetloc_RemapState state = fleetloc_REMAP_QUEUED;
  std::string phase;
  double progress = 0.0;  // 0..1
  long long new_version = 0;
  uint32_t tiles_changed = 0, patches_folded = 0, patches_rejected = 0;
  std::string message;
  double t = 0.0;  // the status's stamp, Unix seconds
  bool final() const { return state >= fleetloc_REMAP_DONE; }
};

// "queued", "running", "done", "failed", "rejected".
const char* RemapStateName(fleetloc_RemapState state);
// The wire's command: wire_version, `command_id`, the request's fields, stamped now.
fleetloc_RemapCommand ToIdl(const RemapRequest& request, uint64_t command_id);
RemapProgress FromIdl(const fleetloc_RemapStatus& status);
// The wire's status: wire_version and every field of `progress` but its time, the status stamped
// `stamp` instead (the sender's clock when it publishes).
fleetloc_RemapStatus ToIdl(const RemapProgress& progress, const fleetloc_TimeStamp& stamp);
nlohmann::json ToJson(const RemapProgress& progress);

}  // namespace fleetloc::transport
