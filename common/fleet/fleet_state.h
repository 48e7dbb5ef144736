// The supervisor's picture of the fleet: every vehicle's newest pose and health, when it was last
// heard from, a short trail of recent positions, and its alerts (raised and cleared with
// hysteresis by VehicleAlerts). Not thread-safe: the supervisor guards it with one mutex.
//
// Silence is a per-vehicle last-seen timeout on the supervisor's clock, not DDS deadline or
// liveliness status: Cyclone's requested-deadline-missed status names only the last instance that
// missed (several vehicles going silent at once would be folded into one), and liveliness is per
// writer, not per vehicle (a simulator publishing 500 vehicles has one writer). The DDS deadline
// status is still read and counted by the supervisor as a cross-check.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fleet/vehicle_alerts.h"
#include "fleet/vehicle_samples.h"

namespace fleetloc::fleet {

struct TrailPoint {
  double t = 0.0, x = 0.0, y = 0.0;
};

struct TrailOptions {
  double period_s = 0.25;  // at most one point per period
  double length_s = 10.0;  // points older than this (relative to the newest) are dropped
};

struct VehicleState {
  std::string id;
  std::optional<PoseSample> pose;
  std::optional<HealthSample> health;
  double last_seen = 0.0;  // supervisor clock (Unix seconds) of the newest sample
  long long poses = 0;     // samples received
  long long healths = 0;
  std::deque<TrailPoint> trail;
};

struct FleetSummary {
  int vehicles = 0;
  // Vehicles heard from within the silence alert's time, by newest pose (unknown: no pose yet).
  int tracking = 0, coasting = 0, lost = 0, relocalized = 0, unknown = 0;
  // STALE vehicles (silence alert active): counted here only, never by their last lock state.
  int silent = 0;
  int critical_alerts = 0, warning_alerts = 0;
};

// An alert raised or cleared by Evaluate (cleared ones carry cleared_t).
using AlertChange = Alert;

class FleetState {
 public:
  FleetState(const AlertOptions& alerts, const TrailOptions& trail)
      : alert_options_(alerts), trail_options_(trail) {}

  // A sample received at `now` (supervisor clock). The vehicle is added on its first sample.
  void OnPose(const std::string& vehicle_id, const PoseSample& pose, double now);
  void OnHealth(const std::string& vehicle_id, const HealthSample& health, double now);

  // Runs every vehicle's alert rules at `now`; returns the alerts raised (id 0, to be assigned by
  // the caller with SetAlertId) and cleared since the last call.
  std::vector<AlertChange> Evaluate(double now);
  void SetAlertId(const std::string& vehicle_id, AlertKind kind, long long id);

  // Restoring after a restart: a vehicle as last stored (trail empty) and its open alerts.
  void Restore(const VehicleState& vehicle);
  void RestoreAlert(const Alert& alert);

  // Calls fn(const VehicleState&) for every vehicle in id order.
  template <typename Fn>
  void ForEach(Fn&& fn) const {
    for (const auto& [id, entry] : entries_) fn(entry.state);
  }
  size_t size() const { return entries_.size(); }
  const VehicleState* Find(const std::string& vehicle_id) const;
  // Active alerts, most severe first, then newest first.
  std::vector<Alert> ActiveAlerts() const;
  bool Silent(const std::string& vehicle_id) const;
  FleetSummary Summary() const;

 private:
  struct Entry {
    VehicleState state;
    VehicleAlerts alerts;
    std::map<AlertKind, Alert> open;  // active alerts by kind
  };
  Entry& Touch(const std::string& vehicle_id);
  void AddTrailPoint(VehicleState* vehicle, const PoseSample& pose) const;

  AlertOptions alert_options_;
  TrailOptions trail_options_;
  std::map<std::string, Entry> entries_;
};

}  // namespace fleetloc::fleet
