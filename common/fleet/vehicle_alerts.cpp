// Alert kinds, severities and the value each rule measures.
#include "fleet/vehicle_alerts.h"

#include <cstdio>

namespace fleetloc::fleet {

namespace {

constexpr const char* kKindNames[kAlertKinds] = {"silent",       "lock_lost",
                                                 "uncertainty",  "cycle_overrun",
                                                 "camera_drops", "map_server_unreachable"};

std::string Format(const char* format, double value) {
  char text[96];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

const char* AlertKindName(AlertKind kind) { return kKindNames[static_cast<int>(kind)]; }

std::optional<AlertKind> AlertKindFromName(const std::string& name) {
  for (int k = 0; k < kAlertKinds; ++k) {
    if (name == kKindNames[k]) return static_cast<AlertKind>(k);
  }
  return std::nullopt;
}

const char* SeverityName(Severity severity) {
  return severity == Severity::kCritical ? "critical" : "warning";
}

Severity SeverityOf(AlertKind kind) {
  return kind == AlertKind::kSilent || kind == AlertKind::kLockLost ? Severity::kCritical
                                                                    : Severity::kWarning;
}

const char* HealthLevelName(HealthLevel level) {
  switch (level) {
    case HealthLevel::kOk:
      return "ok";
    case HealthLevel::kWarn:
      return "warn";
    case HealthLevel::kError:
      return "error";
    case HealthLevel::kStale:
      return "stale";
  }
  return "stale";
}

Status Validate(const AlertOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(Validate(o.silent_s, "silent_s"));
  FLEETLOC_RETURN_IF_ERROR(Validate(o.lock_lost, "lock_lost"));
  FLEETLOC_RETURN_IF_ERROR(Validate(o.uncertainty_m, "uncertainty_m"));
  FLEETLOC_RETURN_IF_ERROR(Validate(o.cycle_p95_ms, "cycle_p95_ms"));
  FLEETLOC_RETURN_IF_ERROR(Validate(o.camera_drops_per_s, "camera_drops_per_s"));
  return Validate(o.map_server_unreachable, "map_server_unreachable");
}

VehicleAlerts::VehicleAlerts(const AlertOptions& o)
    : alarms_{HysteresisAlarm(o.silent_s),           HysteresisAlarm(o.lock_lost),
              HysteresisAlarm(o.uncertainty_m),      HysteresisAlarm(o.cycle_p95_ms),
              HysteresisAlarm(o.camera_drops_per_s), HysteresisAlarm(o.map_server_unreachable)} {}

VehicleAlerts::Measure VehicleAlerts::Measured(AlertKind kind, double now, double last_seen,
                                               const std::optional<PoseSample>& pose,
                                               const std::optional<HealthSample>& health) {
  switch (kind) {
    case AlertKind::kSilent: {
      const double age = now - last_seen;
      return {age, Format("no pose or health for %.1f s", age)};
    }
    case AlertKind::kLockLost: {
      if (!pose) return {};
      return {pose->lock == localization::LockState::kLost ? 1.0 : 0.0, "localization lost"};
    }
    case AlertKind::kUncertainty: {
      if (!pose) return {};
      return {pose->deviation_range_m,
              Format("position uncertainty %.1f mm (3 sigma)", pose->deviation_range_m * 1e3)};
    }
    case AlertKind::kCycleOverrun: {
      if (!health) return {};
      return {health->cycle_ms_p95, Format("tracker cycle p95 %.1f ms", health->cycle_ms_p95)};
    }
    case AlertKind::kCameraDrops: {
      if (!health) return {};
      if (previous_health_ && health->t > previous_health_->t &&
          health->camera_frame_drops >= previous_health_->camera_frame_drops) {
        drops_per_s_ =
            static_cast<double>(health->camera_frame_drops - previous_health_->camera_frame_drops) /
            (health->t - previous_health_->t);
      }
      if (!previous_health_ || health->t > previous_health_->t) previous_health_ = health;
      return {drops_per_s_, Format("%.1f camera frames dropped per second", drops_per_s_)};
    }
    case AlertKind::kMapServerUnreachable: {
      if (!health) return {};
      return {health->map_server_reachable ? 0.0 : 1.0, "vehicle cannot reach the map server"};
    }
  }
  return {};
}

}  // namespace fleetloc::fleet
