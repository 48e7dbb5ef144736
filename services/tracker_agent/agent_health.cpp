// VehicleHealth filling from the counts and the DDS side's state.
#include "tracker_agent/agent_health.h"

#include <cmath>

#include "transport/pose_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::tracker_agent {

void AgentHealth::Fill(const Inputs& in, fleetloc_VehicleHealth* h,
                       std::vector<fleetloc_HealthIssue>* issues) {
  FillFigures(in, h);
  ListIssues(in, issues);
  h->level = fleetloc_HEALTH_OK;
  for (const fleetloc_HealthIssue& issue : *issues) h->level = std::max(h->level, issue.level);
  h->issues._buffer = issues->data();
  h->issues._length = h->issues._maximum = static_cast<uint32_t>(issues->size());
}

void AgentHealth::FillFigures(const Inputs& in, fleetloc_VehicleHealth* h) const {
  *h = {};
  h->wire_version = fleetloc_CURRENT_WIRE_VERSION;
  transport::SetBounded(h->vehicle_id, in.vehicle_id);
  h->stamp = transport::NowStamp();
  h->lock_state = transport::ToIdl(lock_state());
  h->cycle_ms_p50 = static_cast<float>(CyclePercentile(50));
  h->cycle_ms_p95 = static_cast<float>(CyclePercentile(95));
  h->cycle_ms_p99 = static_cast<float>(CyclePercentile(99));
  h->inliers = static_cast<uint32_t>(inliers());
  const long long lookups = in.cache.hits + in.cache.misses;
  h->cache_hit_rate = lookups > 0 ? static_cast<float>(in.cache.hits) / lookups : 1.0f;
  h->tiles_pending = static_cast<uint32_t>(in.tiles_pending);
  h->patch_outbox = static_cast<uint32_t>(in.patch_outbox);
  h->map_server_reachable = in.map_server_reachable;
  const long long dropped = dropped_frames() + in.input_dropped;
  h->camera_frame_drops = static_cast<uint64_t>(dropped);
  transport::SetBounded(h->last_error, last_error());
}

void AgentHealth::ListIssues(const Inputs& in, std::vector<fleetloc_HealthIssue>* issues) {
  const long long dropped = dropped_frames() + in.input_dropped;
  issues->clear();
  auto add = [&](const char* name, fleetloc_HealthLevel level, const std::string& message) {
    fleetloc_HealthIssue issue{};
    transport::SetBounded(issue.name, name);
    issue.level = level;
    transport::SetBounded(issue.message, message);
    issues->push_back(issue);
  };
  if (lock_state() == tracking::LockState::kLost) {
    add("lock_lost", fleetloc_HEALTH_ERROR,
        in.place_index_ready ? "localization lost: relocalizing"
                             : "localization lost and no place index yet to relocalize with");
  }
  if (lock_state() == tracking::LockState::kCoasting)
    add("coasting", fleetloc_HEALTH_WARN, "odometry only");
  if (!in.map_server_reachable) {
    add("map_server_unreachable", fleetloc_HEALTH_WARN,
        in.unreachable_servers.empty()
            ? std::string("tracking from the tile cache")
            : in.unreachable_servers + ": their tiles from the cache only");
  }
  if (timeouts_watch_.Recent(in.loader.timeouts, in.host_s)) {
    add("tile_timeouts", fleetloc_HEALTH_WARN,
        std::to_string(in.loader.timeouts) + " tile waits timed out");
  }
  if (const PositionUpdateStats* u = in.position_update; u && u->last_rejected) {
    // While the newest fit was rejected (an issue name alone reads as a problem on the
    // supervisor's dashboard, so all-well is not reported; the summary has the counts).
    const long correction_mm = std::lround(u->last_correction_m * 1000);
    const std::string counts = std::to_string(u->applied) + " of " + std::to_string(u->attempted) +
                               " position updates applied, " + std::to_string(u->rejected) +
                               " rejected; last correction " + std::to_string(correction_mm) +
                               " mm";
    add("position_update_rejected", fleetloc_HEALTH_WARN,
        counts + "; last rejected: " + u->last_reason);
  }
  for (const InputIssue& issue : in.input_issues) {
    add(issue.name.c_str(), issue.error ? fleetloc_HEALTH_ERROR : fleetloc_HEALTH_WARN,
        issue.message);
  }
  if (dropped_watch_.Recent(dropped, in.host_s))
    add("camera_frame_drops", fleetloc_HEALTH_WARN, std::to_string(dropped) + " frames dropped");
  if (outbox_watch_.Recent(in.patch_outbox_dropped, in.host_s)) {
    add("patch_outbox_full", fleetloc_HEALTH_WARN,
        std::to_string(in.patch_outbox_dropped) +
            " patches dropped from the full outbox (oldest, lowest quality)");
  }
}

}  // namespace fleetloc::tracker_agent
