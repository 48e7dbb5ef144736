// JSON summary of a tracked run.
#include "support/tracker_summary.h"

#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <vector>

namespace fleetloc::fleetctl {

nlohmann::json TrackSummary(const run_io::Run& run, const replay::ReplayResult& replayed) {
  const std::vector<double>& ms = replayed.cycle_ms;
  std::map<std::string, int> counts;
  std::vector<double> locked_ms;  // the frames the method located: its time to do the job
  for (size_t i = 0; i < replayed.poses.size(); ++i) {
    const std::string& status = replayed.poses[i].status;
    ++counts[status];
    if ((status == "tracking" || status == "relocalized") && i < ms.size()) {
      locked_ms.push_back(ms[i]);
    }
  }
  nlohmann::json j;
  j["frames"] = replayed.poses.size();
  j["ms_per_frame"] = {
      {"median", replay::Percentile(ms, 50)},
      {"p95", replay::Percentile(ms, 95)},
      {"mean", ms.empty() ? 0.0 : std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size()},
      {"median_locked", replay::Percentile(locked_ms, 50)}};
  j["status_counts"] = counts;
  const double locked = counts["tracking"] + counts["relocalized"];
  j["lock_rate"] = replayed.poses.empty() ? 0.0 : locked / replayed.poses.size();
  if (!run.truth.empty()) {
    const replay::Accuracy a = replay::Evaluate(replayed.poses, run.truth, run.camera.model);
    const double px = run.camera.model.resolution_m;
    j["error"] = {{"position_rms_m", a.position_rms_m},
                  {"position_rms_px", a.position_rms_m / px},
                  {"position_p95_px", a.position_p95_m / px},
                  {"position_max_px", a.position_max_m / px},
                  {"camera_position_rms_px", a.camera_position_rms_m / px},
                  {"camera_position_p95_px", a.camera_position_p95_m / px},
                  {"camera_position_max_px", a.camera_position_max_m / px},
                  {"false_locks", a.false_locks},
                  {"heading_rms_deg", a.heading_rms_rad * 180.0 / M_PI},
                  {"heading_max_deg", a.heading_max_rad * 180.0 / M_PI},
                  {"lost_frames", a.lost_frames},
                  {"longest_unlocked_run", a.longest_unlocked_run}};
  }
  return j;
}

}  // namespace fleetloc::fleetctl
