// The supervisor's state shared between its DDS thread (which applies what it receives and runs
// the alert rules) and the HTTP threads (which read JSON views of it): the fleet, the re-mapping
// jobs seen on RemapStatus, the services heard on ServiceHealth, and the supervisor's counters.
// Every method is thread-safe.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fleet/fleet_state.h"
#include "fleet_link/fleet_listener.h"
#include "fleet_supervisor/history_store.h"
#include "transport/remap_client.h"

namespace fleetloc::metrics {
class FamilyBuilder;
}

namespace fleetloc::fleet_supervisor {

// Event counters (served at /api/stats and in the supervisor's ServiceHealth).
struct SupervisorCounters {
  std::atomic<uint64_t> poses_received{0}, health_received{0}, rejected_samples{0};
  std::atomic<uint64_t> history_rows{0}, history_errors{0}, alerts_raised{0}, alerts_cleared{0};
  std::atomic<uint64_t> http_requests{0}, http_rejected{0}, tiles_served{0}, remaps_started{0};
  std::atomic<uint64_t> stream_snapshots{0}, deadline_misses{0};
  std::atomic<uint64_t> history_queue{0};  // rows waiting for the next write
  // The HTTP front (http_limits.h): what it refused or cut off, and what is open now.
  std::atomic<uint64_t> http_connections_refused{0}, http_head_timeouts{0}, http_heads_too_large{0};
  std::atomic<uint64_t> http_requests_refused{0}, http_busy{0}, http_auth_throttled{0};
  std::atomic<uint64_t> http_streams_refused{0}, http_streams_dropped{0};
  std::atomic<uint64_t> http_address_refused{0};  // over max_connections_per_address
  std::atomic<int64_t> http_connections_open{0}, http_streams_open{0};
  // (name, value) pairs in a fixed order.
  std::vector<std::pair<std::string, uint64_t>> Snapshot() const;
};

// A vehicle's newest pose and when the supervisor last heard from it (its clock).
struct LatestPose {
  std::string vehicle_id;
  fleet::PoseSample pose;
  double last_seen = 0;
};

class SharedFleet {
 public:
  SharedFleet(const fleet::AlertOptions& alerts, const fleet::TrailOptions& trail,
              double history_period_s);

  // DDS thread: applies the samples received at `now`; appends the rows to store (poses thinned
  // to one per vehicle per history period, every health report) and counts rejections.
  void Apply(const fleet_link::Received& in, double now, std::vector<StoredPose>* poses,
             std::vector<StoredHealth>* health);
  // Appends the newest pose of every vehicle whose newest pose was thinned out of the history
  // (at shutdown, so that a restart restores the last known pose).
  void NewestUnstored(std::vector<StoredPose>* poses);
  // Runs the alert rules; returns the changes (raised ones without id: see SetAlertId).
  std::vector<fleet::Alert> Evaluate(double now);
  void SetAlertId(const fleet::Alert& alert, long long id);
  void OnRemapStatus(const std::vector<transport::RemapProgress>& statuses);
  void Restore(const std::vector<fleet::VehicleState>& vehicles,
               const std::vector<fleet::Alert>& open);

  // Views. `mosaic` and `map_server` are filled in by the caller.
  nlohmann::json Snapshot(double now) const;            // the live stream's state
  nlohmann::json Fleet(double now, bool trails) const;  // GET /api/fleet
  std::optional<nlohmann::json> Vehicle(const std::string& id) const;
  nlohmann::json ActiveAlerts() const;
  nlohmann::json RemapJobs() const;
  // Every vehicle with a pose, in id order.
  std::vector<LatestPose> LatestPoses() const;
  // Adds the fleet's Prometheus families (supervisor_metrics.h) to `b`.
  void AddMetrics(metrics::FamilyBuilder* b) const;
  // Whether a map_server reported within `timeout_s` before `now`.
  bool MapServerAlive(double now, double timeout_s) const;

  SupervisorCounters& counters() { return counters_; }
  const SupervisorCounters& counters() const { return counters_; }

 private:
  nlohmann::json ServicesJson(double now) const;
  nlohmann::json VehiclesJson(bool trails) const;
  nlohmann::json AlertsJson() const;
  nlohmann::json JobsJson() const;

  mutable std::mutex mutex_;
  fleet::FleetState fleet_;
  double history_period_s_;
  std::map<std::string, double> last_stored_;  // per vehicle: receive time of the last stored pose
  // Re-mapping jobs by command and server: with the mosaic split, every server runs each command.
  std::map<std::pair<uint64_t, std::string>, transport::RemapProgress> jobs_;
  std::map<std::string, std::pair<fleet_link::ServiceReport, double>>
      services_;  // with the received time
  std::string last_rejection_;
  SupervisorCounters counters_;
};

}  // namespace fleetloc::fleet_supervisor
