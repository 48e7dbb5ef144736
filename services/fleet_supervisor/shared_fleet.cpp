// SharedFleet: the guarded fleet state and its JSON views.
#include "fleet_supervisor/shared_fleet.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "fleet_link/fleet_view.h"
#include "fleet_supervisor/supervisor_metrics.h"
#include "fleet_supervisor/supervisor_view.h"

namespace fleetloc::fleet_supervisor {

using nlohmann::json;

namespace {
constexpr size_t kMaxJobs = 50;  // newest re-mapping jobs kept for the page
}

std::vector<std::pair<std::string, uint64_t>> SupervisorCounters::Snapshot() const {
  return {
      {"poses_received", poses_received},
      {"health_received", health_received},
      {"rejected_samples", rejected_samples},
      {"history_rows", history_rows},
      {"history_errors", history_errors},
      {"history_queue", history_queue},
      {"alerts_raised", alerts_raised},
      {"alerts_cleared", alerts_cleared},
      {"http_requests", http_requests},
      {"http_rejected", http_rejected},
      {"tiles_served", tiles_served},
      {"remaps_started", remaps_started},
      {"stream_snapshots", stream_snapshots},
      {"deadline_misses", deadline_misses},
      {"http_connections_refused", http_connections_refused},
      {"http_head_timeouts", http_head_timeouts},
      {"http_heads_too_large", http_heads_too_large},
      {"http_requests_refused", http_requests_refused},
      {"http_busy", http_busy},
      {"http_auth_throttled", http_auth_throttled},
      {"http_streams_refused", http_streams_refused},
      {"http_streams_dropped", http_streams_dropped},
      {"http_address_refused", http_address_refused},
      {"http_connections_open", static_cast<uint64_t>(std::max<int64_t>(0, http_connections_open))},
      {"http_streams_open", static_cast<uint64_t>(std::max<int64_t>(0, http_streams_open))}};
}

SharedFleet::SharedFleet(const fleet::AlertOptions& alerts, const fleet::TrailOptions& trail,
                         double history_period_s)
    : fleet_(alerts, trail), history_period_s_(history_period_s) {}

void SharedFleet::Apply(const fleet_link::Received& in, double now, std::vector<StoredPose>* poses,
                        std::vector<StoredHealth>* health) {
  std::lock_guard lock(mutex_);
  for (const auto& [id, pose] : in.poses) {
    fleet_.OnPose(id, pose, now);
    double& last = last_stored_[id];
    if (now >= last + history_period_s_) {
      last = now;
      poses->push_back({id, now, pose});
    }
  }
  for (const auto& [id, h] : in.health) {
    fleet_.OnHealth(id, h, now);
    health->push_back({id, now, h});
  }
  for (const fleet_link::ServiceReport& s : in.services) services_[s.service_id] = {s, now};
  counters_.poses_received += in.poses.size();
  counters_.health_received += in.health.size();
  counters_.rejected_samples += in.rejections.size();
  if (!in.rejections.empty()) {
    last_rejection_ = in.rejections.back();
    spdlog::warn("rejected {} sample(s), last: {}", in.rejections.size(), last_rejection_);
  }
}

void SharedFleet::NewestUnstored(std::vector<StoredPose>* poses) {
  std::lock_guard lock(mutex_);
  fleet_.ForEach([&](const fleet::VehicleState& v) {
    double& last = last_stored_[v.id];
    if (v.pose && last < v.last_seen) {
      poses->push_back({v.id, v.last_seen, *v.pose});
      last = v.last_seen;
    }
  });
}

std::vector<fleet::Alert> SharedFleet::Evaluate(double now) {
  std::lock_guard lock(mutex_);
  std::vector<fleet::Alert> changes = fleet_.Evaluate(now);
  for (const fleet::Alert& a : changes)
    ++(a.cleared_t ? counters_.alerts_cleared : counters_.alerts_raised);
  return changes;
}

void SharedFleet::SetAlertId(const fleet::Alert& alert, long long id) {
  std::lock_guard lock(mutex_);
  fleet_.SetAlertId(alert.vehicle_id, alert.kind, id);
}

void SharedFleet::OnRemapStatus(const std::vector<transport::RemapProgress>& statuses) {
  std::lock_guard lock(mutex_);
  for (const transport::RemapProgress& s : statuses) {
    auto [it, added] = jobs_.try_emplace({s.command_id, s.server_id}, s);
    if (!added && (s.t >= it->second.t || s.final())) it->second = s;
  }
  while (jobs_.size() > kMaxJobs) {
    auto oldest = std::min_element(jobs_.begin(), jobs_.end(), [](const auto& a, const auto& b) {
      return a.second.t < b.second.t;
    });
    jobs_.erase(oldest);
  }
}

void SharedFleet::Restore(const std::vector<fleet::VehicleState>& vehicles,
                          const std::vector<fleet::Alert>& open) {
  std::lock_guard lock(mutex_);
  for (const fleet::VehicleState& v : vehicles) {
    fleet_.Restore(v);
    last_stored_[v.id] = v.last_seen;
  }
  for (const fleet::Alert& a : open) fleet_.RestoreAlert(a);
}

json SharedFleet::VehiclesJson(bool trails) const {
  json vehicles = json::array();
  fleet_.ForEach([&](const fleet::VehicleState& v) {
    vehicles.push_back(fleet_link::VehicleJson(v, fleet_.Silent(v.id), trails));
  });
  return vehicles;
}

json SharedFleet::ServicesJson(double now) const {
  json services = json::array();
  for (const auto& [id, entry] : services_) {
    const auto& [report, received] = entry;
    services.push_back({{"id", id},
                        {"kind", report.kind},
                        {"level", fleet::HealthLevelName(report.level)},
                        {"age_s", now - received}});
  }
  return services;
}

json SharedFleet::AlertsJson() const {
  json alerts = json::array();
  for (const fleet::Alert& a : fleet_.ActiveAlerts()) alerts.push_back(fleet_link::AlertJson(a));
  return alerts;
}

json SharedFleet::JobsJson() const {
  json jobs = json::array();
  for (const auto& [id, job] : jobs_) jobs.push_back(RemapJobJson(job));
  return jobs;
}

json SharedFleet::Snapshot(double now) const {
  std::lock_guard lock(mutex_);
  return {{"t", now},
          {"summary", fleet_link::SummaryJson(fleet_.Summary())},
          {"vehicles", VehiclesJson(false)},
          {"alerts", AlertsJson()},
          {"remap_jobs", JobsJson()},
          {"services", ServicesJson(now)}};
}

json SharedFleet::Fleet(double now, bool trails) const {
  std::lock_guard lock(mutex_);
  return {{"t", now},
          {"summary", fleet_link::SummaryJson(fleet_.Summary())},
          {"vehicles", VehiclesJson(trails)},
          {"services", ServicesJson(now)}};
}

std::optional<json> SharedFleet::Vehicle(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const fleet::VehicleState* v = fleet_.Find(id);
  if (!v) return std::nullopt;
  return fleet_link::VehicleJson(*v, fleet_.Silent(id), true);
}

json SharedFleet::ActiveAlerts() const {
  std::lock_guard lock(mutex_);
  return AlertsJson();
}

json SharedFleet::RemapJobs() const {
  std::lock_guard lock(mutex_);
  return JobsJson();
}

std::vector<LatestPose> SharedFleet::LatestPoses() const {
  std::lock_guard lock(mutex_);
  std::vector<LatestPose> out;
  out.reserve(fleet_.size());
  fleet_.ForEach([&](const fleet::VehicleState& v) {
    if (v.pose) out.push_back({v.id, *v.pose, v.last_seen});
  });
  return out;
}

void SharedFleet::AddMetrics(metrics::FamilyBuilder* b) const {
  std::lock_guard<std::mutex> lock(mutex_);
  AddFleetFamilies(fleet_, b);
}

bool SharedFleet::MapServerAlive(double now, double timeout_s) const {
  std::lock_guard lock(mutex_);
  for (const auto& [id, entry] : services_) {
    if (entry.first.kind == "map_server" && now - entry.second <= timeout_s) return true;
  }
  return false;
}

}  // namespace fleetloc::fleet_supervisor
