// The alert rules of one vehicle: which conditions the supervisor watches (silence, lost lock,
// growing uncertainty, cycle-time overrun, camera frame drops, map server unreachable), the value
// each rule measures, its severity and its hysteresis.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "fleet/alert_rule.h"
#include "fleet/vehicle_samples.h"

namespace fleetloc::fleet {

enum class AlertKind {
  kSilent,
  kLockLost,
  kUncertainty,
  kCycleOverrun,
  kCameraDrops,
  kMapServerUnreachable
};
inline constexpr int kAlertKinds = 6;
enum class Severity { kWarning, kCritical };

const char* AlertKindName(AlertKind kind);
// The kind named `name` (as AlertKindName), or nullopt.
std::optional<AlertKind> AlertKindFromName(const std::string& name);
const char* SeverityName(Severity severity);
Severity SeverityOf(AlertKind kind);

// Thresholds of each rule; the measured value is in the field name's unit.
struct AlertOptions {
  // Seconds since the last pose or health sample (a last-seen timeout: see FleetState).
  HysteresisOptions silent_s{3.0, 1.0, 0.0, 1.0};
  // 1 while the vehicle reports lock lost, else 0.
  HysteresisOptions lock_lost{0.5, 0.5, 1.0, 2.0};
  // Deviation range (3 sigma of position, metres) of the newest pose.
  HysteresisOptions uncertainty_m{0.02, 0.01, 1.0, 3.0};
  // The tracker cycle's 95th percentile (ms) in the newest health report.
  HysteresisOptions cycle_p95_ms{50.0, 35.0, 3.0, 5.0};
  // Camera frames dropped per second between the last two health reports.
  HysteresisOptions camera_drops_per_s{0.5, 0.05, 0.0, 10.0};
  // 1 while the vehicle reports the map server unreachable, else 0.
  HysteresisOptions map_server_unreachable{0.5, 0.5, 3.0, 3.0};
};

Status Validate(const AlertOptions& options);

// A raised or cleared alert (the supervisor keeps active ones and stores every change).
struct Alert {
  long long id = 0;  // assigned by the store; 0 until then
  std::string vehicle_id;
  AlertKind kind = AlertKind::kSilent;
  Severity severity = Severity::kWarning;
  double raised_t = 0.0;  // Unix seconds
  std::optional<double> cleared_t;
  std::string message;
};

// The alarms of one vehicle.
class VehicleAlerts {
 public:
  explicit VehicleAlerts(const AlertOptions& options);

  // Evaluates every rule at `now` on the vehicle's newest samples (`last_seen`: when the last
  // one arrived). Calls on_change(kind, raised, message) for each rule that changed. While the
  // vehicle is silent only the silence rule runs: the others keep their state (the last known).
  template <typename Fn>
  void Evaluate(double now, double last_seen, const std::optional<PoseSample>& pose,
                const std::optional<HealthSample>& health, Fn&& on_change);

  bool active(AlertKind kind) const { return alarms_[static_cast<int>(kind)].active(); }
  void Force(AlertKind kind, bool active) { alarms_[static_cast<int>(kind)].Force(active); }

 private:
  // The value of each rule (nullopt: no data for it yet) and a message for the operator.
  struct Measure {
    std::optional<double> value;
    std::string message;
  };
  Measure Measured(AlertKind kind, double now, double last_seen,
                   const std::optional<PoseSample>& pose,
                   const std::optional<HealthSample>& health);

  std::array<HysteresisAlarm, kAlertKinds> alarms_;
  std::optional<HealthSample> previous_health_;  // for the drop rate
  double drops_per_s_ = 0.0;
};

template <typename Fn>
void VehicleAlerts::Evaluate(double now, double last_seen, const std::optional<PoseSample>& pose,
                             const std::optional<HealthSample>& health, Fn&& on_change) {
  for (int k = 0; k < kAlertKinds; ++k) {
    const auto kind = static_cast<AlertKind>(k);
    if (kind != AlertKind::kSilent && active(AlertKind::kSilent)) continue;
    const Measure m = Measured(kind, now, last_seen, pose, health);
    if (!m.value) continue;
    const HysteresisAlarm::Change change = alarms_[k].Update(now, *m.value);
    if (change != HysteresisAlarm::Change::kNone) {
      on_change(kind, change == HysteresisAlarm::Change::kRaised, m.message);
    }
  }
}

}  // namespace fleetloc::fleet
