// Supervisor metric families.
#include "fleet_supervisor/supervisor_metrics.h"

namespace fleetloc::fleet_supervisor {

void AddFleetFamilies(const fleet::FleetState& fleet, metrics::FamilyBuilder* b) {
  const fleet::FleetSummary s = fleet.Summary();
  const char* by_lock = "Vehicles by the lock state of their newest pose (unknown: no pose yet)";
  const std::pair<const char*, int> states[] = {{"tracking", s.tracking},
                                                {"coasting", s.coasting},
                                                {"lost", s.lost},
                                                {"relocalized", s.relocalized},
                                                {"unknown", s.unknown}};
  for (const auto& [state, n] : states) b->Gauge("vehicles", by_lock, n, {{"lock_state", state}});
  b->Gauge("vehicles_silent", "Vehicles not heard from within the silence alert's time", s.silent);
  const char* alerts = "Open alerts by severity";
  b->Gauge("alerts_open", alerts, s.critical_alerts, {{"severity", "critical"}});
  b->Gauge("alerts_open", alerts, s.warning_alerts, {{"severity", "warning"}});
  fleet.ForEach([&](const fleet::VehicleState& v) {
    if (!v.health) return;
    const fleet::HealthSample& h = *v.health;
    const metrics::Labels id = {{"vehicle_id", v.id}};
    b->Gauge("vehicle_cycle_seconds",
             "A vehicle's tracker cycle time over its recent frames, by quantile",
             h.cycle_ms_p50 / 1000, {{"vehicle_id", v.id}, {"quantile", "0.5"}});
    b->Gauge("vehicle_cycle_seconds", "", h.cycle_ms_p95 / 1000,
             {{"vehicle_id", v.id}, {"quantile", "0.95"}});
    b->Gauge("vehicle_cycle_seconds", "", h.cycle_ms_p99 / 1000,
             {{"vehicle_id", v.id}, {"quantile", "0.99"}});
    b->Gauge("vehicle_tile_cache_hit_ratio", "A vehicle's tile cache hits / lookups (reported)",
             h.cache_hit_rate, id);
    b->Gauge("vehicle_patch_outbox_patches",
             "Patches in a vehicle's outbox waiting for the map server", h.patch_outbox, id);
    b->Gauge("vehicle_tiles_pending", "Tiles a vehicle has asked for and not yet received",
             h.tiles_pending, id);
    b->Gauge("vehicle_map_server_reachable", "1 when the vehicle hears every map server it needs",
             h.map_server_reachable ? 1 : 0, id);
    b->Counter("vehicle_camera_frame_drops", "Camera frames a vehicle dropped",
               static_cast<double>(h.camera_frame_drops), id);
    b->Gauge("vehicle_last_seen_timestamp_seconds",
             "When the supervisor last heard from the vehicle (Unix time)", v.last_seen, id);
  });
}

void AddSupervisorFamilies(const std::vector<std::pair<std::string, uint64_t>>& counters,
                           bool map_server_alive, metrics::FamilyBuilder* b) {
  b->HealthCounters(counters, {"history_queue", "http_connections_open", "http_streams_open"});
  b->Gauge("map_server_alive", "1 when a map server reported its health within 5 s",
           map_server_alive ? 1 : 0);
}

}  // namespace fleetloc::fleet_supervisor
