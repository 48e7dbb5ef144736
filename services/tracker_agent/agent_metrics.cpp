// Tracker agent metric families.
#include "tracker_agent/agent_metrics.h"

#include <utility>

namespace fleetloc::tracker_agent {

void AddAgentFamilies(const AgentMetricsInput& in, metrics::FamilyBuilder* b) {
  for (const tracking::LockState state :
       {tracking::LockState::kTracking, tracking::LockState::kCoasting, tracking::LockState::kLost,
        tracking::LockState::kRelocalized}) {
    b->Gauge("lock_state", "1 for the vehicle's current lock state, 0 for the others",
             in.lock_state == state ? 1 : 0, {{"lock_state", tracking::LockStateName(state)}});
  }
  b->Counter("frames", "Camera frames tracked", static_cast<double>(in.frames));
  b->Histogram("cycle_seconds", "Tracker cycle time per frame", in.cycle_seconds);
  b->Histogram("tile_round_trip_seconds", "From a tile request to the map server's answer",
               in.tile_round_trip_seconds);
  const long long lookups = in.cache.hits + in.cache.misses;
  b->Gauge("tile_cache_hit_ratio", "Tile cache hits / lookups since start (1 before any lookup)",
           lookups > 0 ? static_cast<double>(in.cache.hits) / static_cast<double>(lookups) : 1.0);
  b->Gauge("tile_cache_bytes", "Decoded tile bytes cached", static_cast<double>(in.cache.bytes));
  b->Gauge("tiles_pending", "Tiles asked for and not yet received",
           static_cast<double>(in.tiles_pending));
  const std::pair<const char*, long long> loader[] = {
      {"requested", in.loader.requested}, {"received", in.loader.received},
      {"waited", in.loader.waited},       {"timeouts", in.loader.timeouts},
      {"unserved", in.loader.unserved},   {"errors", in.loader.errors},
      {"stale", in.loader.stale},         {"reasked", in.loader.reasked}};
  for (const auto& [event, n] : loader) {
    b->Counter("tile_loads", "Tile loader events by kind (DdsTileLoaderStats)",
               static_cast<double>(n), {{"event", event}});
  }
  b->Gauge("patch_outbox_patches", "Patches in the outbox waiting for the map server's ack",
           static_cast<double>(in.outbox_patches));
  b->Counter("patch_outbox_dropped", "Patches the full outbox dropped",
             static_cast<double>(in.outbox_dropped));
  b->Gauge("map_server_reachable", "1 when every map server the vehicle needs reports",
           in.map_server_reachable ? 1 : 0);
  b->Counter("relocalization_attempts", "Global relocalization attempts",
             static_cast<double>(in.relocalization_attempts));
  b->Counter("relocalization_found", "Global relocalization attempts that found a pose",
             static_cast<double>(in.relocalization_found));
}

}  // namespace fleetloc::tracker_agent
