// RemapCommand and RemapStatus to and from plain values.
#include "transport/remap_messages.h"

#include "transport/wire_util.h"

namespace fleetloc::transport {

const char* RemapStateName(fleetloc_RemapState state) {
  switch (state) {
    case fleetloc_REMAP_QUEUED:
      return "queued";
    case fleetloc_REMAP_RUNNING:
      return "running";
    case fleetloc_REMAP_DONE:
      return "done";
    case fleetloc_REMAP_FAILED:
      return "failed";
    case fleetloc_REMAP_REJECTED:
      return "rejected";
  }
  return "unknown";
}

fleetloc_RemapCommand ToIdl(const RemapRequest& r, uint64_t command_id) {
  fleetloc_RemapCommand command{};
  command.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  command.command_id = command_id;
  SetBounded(command.requester, r.requester);
  SetBounded(command.mosaic_id, r.mosaic_id);
  command.region = {r.x_min, r.y_min, r.x_max, r.y_max};
  command.mode = r.replace ? fleetloc_REMAP_REPLACE : fleetloc_REMAP_BLEND;
  command.stamp = NowStamp();
  return command;
}

RemapProgress FromIdl(const fleetloc_RemapStatus& s) {
  RemapProgress p;
  p.command_id = s.command_id;
  p.server_id = GetBounded(s.server_id);
  p.state = s.state;
  p.phase = GetBounded(s.phase);
  p.progress = s.progress;
  p.new_version = s.new_version;
  p.tiles_changed = s.tiles_changed;
  p.patches_folded = s.patches_folded;
  p.patches_rejected = s.patches_rejected;
  p.message = GetBounded(s.message);
  p.t = ToSeconds(s.stamp);
  return p;
}

fleetloc_RemapStatus ToIdl(const RemapProgress& p, const fleetloc_TimeStamp& stamp) {
  fleetloc_RemapStatus status{};
  status.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  status.command_id = p.command_id;
  SetBounded(status.server_id, p.server_id);
  status.state = p.state;
  SetBounded(status.phase, p.phase);
  status.progress = static_cast<float>(p.progress);
  SetBounded(status.message, p.message);
  status.stamp = stamp;
  status.new_version = p.new_version;
  status.tiles_changed = p.tiles_changed;
  status.patches_folded = p.patches_folded;
  status.patches_rejected = p.patches_rejected;
  return status;
}

nlohmann::json ToJson(const RemapProgress& p) {
  return {{"command_id", p.command_id},
          {"server_id", p.server_id},
          {"state", RemapStateName(p.state)},
          {"phase", p.phase},
          {"progress", p.progress},
          {"new_version", p.new_version},
          {"tiles_changed", p.tiles_changed},
          {"patches_folded", p.patches_folded},
          {"patches_rejected", p.patches_rejected},
          {"message", p.message},
          {"t", p.t}};
}

}  // namespace fleetloc::transport
