// FleetState: newest samples, trails, alert bookkeeping.
#include "fleet/fleet_state.h"

#include <algorithm>

namespace fleetloc::fleet {

FleetState::Entry& FleetState::Touch(const std::string& vehicle_id) {
  auto it = entries_.find(vehicle_id);
  if (it == entries_.end()) {
    it = entries_.emplace(vehicle_id, Entry{VehicleState{}, VehicleAlerts(alert_options_), {}})
             .first;
    it->second.state.id = vehicle_id;
  }
  return it->second;
}

void FleetState::AddTrailPoint(VehicleState* v, const PoseSample& pose) const {
  if (!v->trail.empty() && pose.t < v->trail.back().t + trail_options_.period_s) return;
  v->trail.push_back({pose.t, pose.x, pose.y});
  while (!v->trail.empty() && v->trail.front().t < pose.t - trail_options_.length_s) {
    v->trail.pop_front();
  }
}

void FleetState::OnPose(const std::string& vehicle_id, const PoseSample& pose, double now) {
  VehicleState& v = Touch(vehicle_id).state;
  if (v.pose && pose.t < v.pose->t) return;  // an older sample overtaken by a newer one
  v.pose = pose;
  v.last_seen = std::max(v.last_seen, now);
  ++v.poses;
  AddTrailPoint(&v, pose);
}

void FleetState::OnHealth(const std::string& vehicle_id, const HealthSample& health, double now) {
  VehicleState& v = Touch(vehicle_id).state;
  if (v.health && health.t < v.health->t) return;
  v.health = health;
  v.last_seen = std::max(v.last_seen, now);
  ++v.healths;
}

std::vector<AlertChange> FleetState::Evaluate(double now) {
  std::vector<AlertChange> changes;
  for (auto& [id, entry] : entries_) {
    const VehicleState& v = entry.state;
    entry.alerts.Evaluate(
        now, v.last_seen, v.pose, v.health,
        [&, &id = id, &entry = entry](AlertKind kind, bool raised, const std::string& message) {
          if (raised) {
            Alert alert{0, id, kind, SeverityOf(kind), now, std::nullopt, message};
            entry.open[kind] = alert;
            changes.push_back(alert);
            return;
          }
          auto open = entry.open.find(kind);
          if (open == entry.open.end()) return;
          open->second.cleared_t = now;
          changes.push_back(open->second);
          entry.open.erase(open);
        });
  }
  return changes;
}

void FleetState::SetAlertId(const std::string& vehicle_id, AlertKind kind, long long id) {
  auto entry = entries_.find(vehicle_id);
  if (entry == entries_.end()) return;
  auto open = entry->second.open.find(kind);
  if (open != entry->second.open.end()) open->second.id = id;
}

void FleetState::Restore(const VehicleState& vehicle) {
  Entry& entry = Touch(vehicle.id);
  entry.state = vehicle;
}

void FleetState::RestoreAlert(const Alert& alert) {
  if (alert.cleared_t) return;
  Entry& entry = Touch(alert.vehicle_id);
  entry.open[alert.kind] = alert;
  entry.alerts.Force(alert.kind, true);
}

const VehicleState* FleetState::Find(const std::string& vehicle_id) const {
  auto it = entries_.find(vehicle_id);
  return it == entries_.end() ? nullptr : &it->second.state;
}

std::vector<Alert> FleetState::ActiveAlerts() const {
  std::vector<Alert> active;
  for (const auto& [id, entry] : entries_) {
    for (const auto& [kind, alert] : entry.open) active.push_back(alert);
  }
  std::sort(active.begin(), active.end(), [](const Alert& a, const Alert& b) {
    if (a.severity != b.severity) return a.severity > b.severity;
    return a.raised_t > b.raised_t;
  });
  return active;
}

bool FleetState::Silent(const std::string& vehicle_id) const {
  auto it = entries_.find(vehicle_id);
  return it != entries_.end() && it->second.alerts.active(AlertKind::kSilent);
}

FleetSummary FleetState::Summary() const {
  FleetSummary s;
  for (const auto& [id, entry] : entries_) {
    ++s.vehicles;
    const std::optional<PoseSample>& pose = entry.state.pose;
    if (entry.alerts.active(AlertKind::kSilent)) {
      ++s.silent;  // STALE: its last lock state is history, not counted as current
    } else if (!pose) {
      ++s.unknown;
    } else {
      switch (pose->lock) {
        case localization::LockState::kTracking:
          ++s.tracking;
          break;
        case localization::LockState::kCoasting:
          ++s.coasting;
          break;
        case localization::LockState::kLost:
          ++s.lost;
          break;
        case localization::LockState::kRelocalized:
          ++s.relocalized;
          break;
      }
    }
    for (const auto& [kind, alert] : entry.open) {
      ++(alert.severity == Severity::kCritical ? s.critical_alerts : s.warning_alerts);
    }
  }
  return s;
}

}  // namespace fleetloc::fleet
