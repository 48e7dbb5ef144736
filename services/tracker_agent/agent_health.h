// The tracker agent's health: cycle-time percentiles over recent frames, inliers, lock state,
// tile cache and loader counters, reachability, dropped frames, the position updates and the last
// error, turned into a VehicleHealth with a level (OK / WARN / ERROR) and named issues.
#pragma once

#include <string>
#include <vector>

#include "mosaic/tile_cache.h"
#include "timing/stream_watch.h"
#include "tracker_agent/agent_position_update.h"
#include "tracker_agent/health_counters.h"
#include "tracker_agent/vehicle_input.h"
#include "transport/dds_tile_loader.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::tracker_agent {

// The counts (HealthCounters) and the VehicleHealth made of them and of the DDS side's state.
class AgentHealth : public HealthCounters {
 public:
  // An issue about a count (frames dropped, tile waits timed out, patches dropped) is named for
  // `issue_hold_s` (the agent's live.issue_hold_s) after the count last rose (timing::CountWatch);
  // the counts stay in the figures.
  explicit AgentHealth(double issue_hold_s)
      : dropped_watch_(issue_hold_s), timeouts_watch_(issue_hold_s), outbox_watch_(issue_hold_s) {}

  struct Inputs {
    std::string vehicle_id;
    mosaic::TileCacheStats cache;
    transport::DdsTileLoaderStats loader;
    size_t tiles_pending = 0;
    size_t patch_outbox = 0;
    bool map_server_reachable = false;  // every map server owning part of the mosaic
    std::string unreachable_servers;    // their ids when not, comma-separated
    bool place_index_ready = false;     // relocalization possible
    const PositionUpdateStats* position_update = nullptr;  // null: no position updates
    long long patch_outbox_dropped = 0;    // patches the full outbox dropped (ever, this vehicle)
    std::vector<InputIssue> input_issues;  // the live input's (camera, odometry)
    long long input_dropped = 0;           // frames the input lost before the agent saw them
    double host_s = 0.0;                   // when (seconds on a steady clock): for the holds
  };
  // Fills `health` (its issues point into `issue_storage`, which must outlive the write).
  void Fill(const Inputs& in, fleetloc_VehicleHealth* health,
            std::vector<fleetloc_HealthIssue>* issue_storage);

 private:
  // The message's figures, and the issues that explain its level.
  void FillFigures(const Inputs& in, fleetloc_VehicleHealth* health) const;
  void ListIssues(const Inputs& in, std::vector<fleetloc_HealthIssue>* issues);

  timing::CountWatch dropped_watch_, timeouts_watch_, outbox_watch_;
};

}  // namespace fleetloc::tracker_agent
