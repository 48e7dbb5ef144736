// Wire → fleet samples.
#include "fleet_link/fleet_messages.h"

#include <cmath>

#include "transport/pose_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::fleet_link {

using transport::GetBounded;

namespace {

// Checks the fields every top-level type shares; `what` names the topic in messages.
template <size_t N>
Status CheckHeader(unsigned short wire_version, const char (&id)[N], const char* what) {
  const std::string name = GetBounded(id);
  if (wire_version != fleetloc_CURRENT_WIRE_VERSION) {
    return InvalidInput(std::string(what) + " from '" + name + "': wire version " +
                        std::to_string(wire_version) + " (expected " +
                        std::to_string(fleetloc_CURRENT_WIRE_VERSION) + ")");
  }
  if (!transport::IsValidEntityId(name)) {
    return InvalidInput(std::string(what) + ": id '" + name + "' is not 1-11 of [A-Za-z0-9_-]");
  }
  return Status::Ok();
}

fleet::HealthLevel LevelFromIdl(fleetloc_HealthLevel level) {
  switch (level) {
    case fleetloc_HEALTH_OK:
      return fleet::HealthLevel::kOk;
    case fleetloc_HEALTH_WARN:
      return fleet::HealthLevel::kWarn;
    case fleetloc_HEALTH_ERROR:
      return fleet::HealthLevel::kError;
    default:
      return fleet::HealthLevel::kStale;
  }
}

}  // namespace

Result<fleet::PoseSample> PoseFromIdl(const fleetloc_VehiclePose& p) {
  FLEETLOC_RETURN_IF_ERROR(CheckHeader(p.wire_version, p.vehicle_id, "VehiclePose"));
  const transport::PoseReport report = transport::FromIdl(p);
  fleet::PoseSample s;
  s.t = report.t;
  s.x = p.x;
  s.y = p.y;
  s.theta = p.theta;
  s.cov_xx = p.covariance[0];
  s.cov_xy = p.covariance[1];
  s.cov_yy = p.covariance[4];
  s.cov_tt = p.covariance[8];
  s.lock = report.state;
  s.localization_score = p.localization_score;
  s.deviation_range_m = p.deviation_range_m;
  s.mosaic_version = p.mosaic_version;
  for (double v : {s.t, s.x, s.y, s.theta, s.cov_xx, s.cov_xy, s.cov_yy, s.cov_tt,
                   s.localization_score, s.deviation_range_m}) {
    if (!std::isfinite(v)) {
      return InvalidInput("VehiclePose from '" + report.vehicle_id +
                          "': non-finite pose or covariance");
    }
  }
  return s;
}

Result<fleet::HealthSample> HealthFromIdl(const fleetloc_VehicleHealth& h) {
  FLEETLOC_RETURN_IF_ERROR(CheckHeader(h.wire_version, h.vehicle_id, "VehicleHealth"));
  fleet::HealthSample s;
  s.t = transport::ToSeconds(h.stamp);
  s.level = LevelFromIdl(h.level);
  for (uint32_t i = 0; i < h.issues._length && i < 32; ++i)
    s.issues.push_back(GetBounded(h.issues._buffer[i].name));
  s.lock = transport::FromIdl(h.lock_state);
  s.cycle_ms_p50 = h.cycle_ms_p50;
  s.cycle_ms_p95 = h.cycle_ms_p95;
  s.cycle_ms_p99 = h.cycle_ms_p99;
  s.inliers = static_cast<int>(h.inliers);
  s.cache_hit_rate = h.cache_hit_rate;
  s.tiles_pending = static_cast<int>(h.tiles_pending);
  s.patch_outbox = static_cast<int>(h.patch_outbox);
  s.map_server_reachable = h.map_server_reachable;
  s.camera_frame_drops = h.camera_frame_drops;
  s.last_error = GetBounded(h.last_error);
  for (double v : {s.t, s.cycle_ms_p50, s.cycle_ms_p95, s.cycle_ms_p99, s.cache_hit_rate}) {
    if (!std::isfinite(v)) {
      return InvalidInput("VehicleHealth from '" + GetBounded(h.vehicle_id) +
                          "': non-finite field");
    }
  }
  return s;
}

Result<ServiceReport> ServiceFromIdl(const fleetloc_ServiceHealth& h) {
  FLEETLOC_RETURN_IF_ERROR(CheckHeader(h.wire_version, h.service_id, "ServiceHealth"));
  ServiceReport report{GetBounded(h.service_id),
                       GetBounded(h.kind),
                       LevelFromIdl(h.level),
                       transport::ToSeconds(h.stamp),
                       {}};
  for (uint32_t i = 0; i < h.counters._length; ++i) {
    report.counters[GetBounded(h.counters._buffer[i].name)] = h.counters._buffer[i].value;
  }
  return report;
}

}  // namespace fleetloc::fleet_link
