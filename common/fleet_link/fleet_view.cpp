// JSON of vehicles, alerts and the fleet summary.
#include "fleet_link/fleet_view.h"

namespace fleetloc::fleet_link {

using nlohmann::json;

namespace {

json PoseJson(const fleet::PoseSample& p) {
  return {{"t", p.t},
          {"x", p.x},
          {"y", p.y},
          {"theta", p.theta},
          {"cov", {p.cov_xx, p.cov_xy, p.cov_yy, p.cov_tt}},
          {"lock", localization::LockStateName(p.lock)},
          {"score", p.localization_score},
          {"deviation_m", p.deviation_range_m},
          {"mosaic_version", p.mosaic_version}};
}

json HealthJson(const fleet::HealthSample& h) {
  return {{"t", h.t},
          {"level", fleet::HealthLevelName(h.level)},
          {"issues", h.issues},
          {"lock", localization::LockStateName(h.lock)},
          {"cycle_ms", {h.cycle_ms_p50, h.cycle_ms_p95, h.cycle_ms_p99}},
          {"inliers", h.inliers},
          {"cache_hit_rate", h.cache_hit_rate},
          {"tiles_pending", h.tiles_pending},
          {"patch_outbox", h.patch_outbox},
          {"map_server_reachable", h.map_server_reachable},
          {"camera_frame_drops", h.camera_frame_drops},
          {"last_error", h.last_error}};
}

}  // namespace

json VehicleJson(const fleet::VehicleState& v, bool silent, bool trail) {
  json out = {{"id", v.id},
              {"last_seen", v.last_seen},
              {"silent", silent},
              {"poses_received", v.poses},
              {"health_received", v.healths},
              {"pose", v.pose ? PoseJson(*v.pose) : json(nullptr)},
              {"health", v.health ? HealthJson(*v.health) : json(nullptr)}};
  if (silent && v.health) {  // its last report is history: the level says so, the report is kept
    out["health"]["reported_level"] = out["health"]["level"];
    out["health"]["level"] = fleet::HealthLevelName(fleet::HealthLevel::kStale);
  }
  if (trail) {
    json points = json::array();
    for (const fleet::TrailPoint& p : v.trail) points.push_back({p.t, p.x, p.y});
    out["trail"] = std::move(points);
  }
  return out;
}

json AlertJson(const fleet::Alert& a) {
  return {{"id", a.id},
          {"vehicle", a.vehicle_id},
          {"kind", fleet::AlertKindName(a.kind)},
          {"severity", fleet::SeverityName(a.severity)},
          {"raised", a.raised_t},
          {"cleared", a.cleared_t ? json(*a.cleared_t) : json(nullptr)},
          {"active", !a.cleared_t.has_value()},
          {"message", a.message}};
}

json SummaryJson(const fleet::FleetSummary& s) {
  return {{"vehicles", s.vehicles},
          {"tracking", s.tracking},
          {"coasting", s.coasting},
          {"lost", s.lost},
          {"relocalized", s.relocalized},
          {"unknown", s.unknown},
          {"silent", s.silent},
          {"critical_alerts", s.critical_alerts},
          {"warning_alerts", s.warning_alerts}};
}

}  // namespace fleetloc::fleet_link
