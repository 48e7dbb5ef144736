// JSON of readiness, re-mapping jobs and history.
#include "fleet_supervisor/supervisor_view.h"

#include <algorithm>
#include <set>

#include "fleet/history_decimation.h"

namespace fleetloc::fleet_supervisor {

using nlohmann::json;

namespace {

// Sorted union of the indices two decimations keep.
std::vector<size_t> Union(const std::vector<size_t>& a, const std::vector<size_t>& b) {
  std::set<size_t> all(a.begin(), a.end());
  all.insert(b.begin(), b.end());
  return {all.begin(), all.end()};
}

}  // namespace

json ReadinessJson(const std::vector<ReadinessCheck>& checks, bool* ready) {
  *ready = true;
  json out = {{"checks", json::object()}};
  for (const ReadinessCheck& c : checks) {
    *ready = *ready && c.ok;
    out["checks"][c.name] = {{"ok", c.ok}, {"detail", c.detail}};
  }
  out["ready"] = *ready;
  return out;
}

json RemapJobJson(const transport::RemapProgress& job) {
  json out = transport::ToJson(job);
  out["command_id"] = std::to_string(job.command_id);
  return out;
}

json PoseHistoryJson(const std::vector<StoredPose>& poses, size_t max_points) {
  std::vector<double> t, deviation;
  for (const StoredPose& p : poses) {
    t.push_back(p.received);
    deviation.push_back(p.pose.deviation_range_m);
  }
  json out = {{"t", json::array()},     {"x", json::array()},           {"y", json::array()},
              {"theta", json::array()}, {"deviation_m", json::array()}, {"score", json::array()},
              {"lock", json::array()}};
  for (size_t i : fleet::DecimateMinMax(t, deviation, max_points)) {
    const fleet::PoseSample& p = poses[i].pose;
    out["t"].push_back(poses[i].received);
    out["x"].push_back(p.x);
    out["y"].push_back(p.y);
    out["theta"].push_back(p.theta);
    out["deviation_m"].push_back(p.deviation_range_m);
    out["score"].push_back(p.localization_score);
    out["lock"].push_back(localization::LockStateName(p.lock));
  }
  return out;
}

json HealthHistoryJson(const std::vector<StoredHealth>& health, size_t max_points) {
  std::vector<double> t, cycle, inliers;
  for (const StoredHealth& h : health) {
    t.push_back(h.received);
    cycle.push_back(h.health.cycle_ms_p95);
    inliers.push_back(h.health.inliers);
  }
  json out = {{"t", json::array()},
              {"cycle_ms_p50", json::array()},
              {"cycle_ms_p95", json::array()},
              {"inliers", json::array()},
              {"level", json::array()},
              {"camera_frame_drops", json::array()}};
  const size_t half = std::max<size_t>(2, max_points / 2);
  for (size_t i :
       Union(fleet::DecimateMinMax(t, cycle, half), fleet::DecimateMinMax(t, inliers, half))) {
    const fleet::HealthSample& h = health[i].health;
    out["t"].push_back(health[i].received);
    out["cycle_ms_p50"].push_back(h.cycle_ms_p50);
    out["cycle_ms_p95"].push_back(h.cycle_ms_p95);
    out["inliers"].push_back(h.inliers);
    out["level"].push_back(fleet::HealthLevelName(h.level));
    out["camera_frame_drops"].push_back(h.camera_frame_drops);
  }
  return out;
}

}  // namespace fleetloc::fleet_supervisor
