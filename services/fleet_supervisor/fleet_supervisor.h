// The fleet supervisor: gathers every vehicle's pose and health and the re-mapping jobs over DDS,
// raises and clears alerts, keeps the history in SQLite (restored after a restart), publishes its
// own ServiceHealth, and serves the HTTP API, live stream and dashboard (HttpApi). One thread
// runs the DDS loop (Run); the HTTP server has its own threads.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "fleet_link/fleet_listener.h"
#include "fleet_supervisor/event_stream.h"
#include "fleet_supervisor/history_store.h"
#include "fleet_supervisor/http_api.h"
#include "fleet_supervisor/overview_tiles.h"
#include "fleet_supervisor/shared_fleet.h"
#include "fleet_supervisor/supervisor_config.h"
#include "fleet_supervisor/vda5050_publisher.h"
#include "metrics/metrics_exporter.h"
#include "transport/remap_client.h"
#include "transport/waitset.h"

namespace fleetloc::fleet_supervisor {

class FleetSupervisor {
 public:
  // Opens the history (restoring the fleet from it), every DDS entity and the HTTP server.
  static Result<std::unique_ptr<FleetSupervisor>> Create(const SupervisorConfig& config);
  ~FleetSupervisor();

  // Runs until `stop` becomes true (checked every 10 ms); then stops the HTTP server.
  Status Run(const std::atomic<bool>& stop);
  int http_port() const { return http_->port(); }
  int metrics_port() const { return metrics_ ? metrics_->port() : 0; }

 private:
  explicit FleetSupervisor(const SupervisorConfig& config);
  Status Open();
  Status Restore();
  void Step(double now);
  void FlushHistory(double now);
  void StoreAlerts(const std::vector<fleet::Alert>& changes);
  Status PublishHealth();
  void RefreshMetrics(double now);
  // Every counter of the supervisor's health: its own and the VDA 5050 publisher's.
  std::vector<std::pair<std::string, uint64_t>> AllCounters() const;
  std::string ResolveWebDir() const;

  SupervisorConfig config_;
  std::unique_ptr<HistoryStore> history_;
  std::unique_ptr<SharedFleet> fleet_;
  EventStream stream_;
  std::unique_ptr<transport::Participant> participant_;
  std::unique_ptr<fleet_link::FleetListener> listener_;
  std::unique_ptr<OverviewTiles> tiles_;
  std::unique_ptr<transport::RemapClient> remap_;
  std::unique_ptr<transport::Topic<fleetloc_ServiceHealth>> health_topic_;
  std::unique_ptr<transport::Writer<fleetloc_ServiceHealth>> health_writer_;
  std::unique_ptr<transport::WaitSet> waitset_;
  // /metrics (config "metrics"); a port that cannot be bound is the health issue
  // "metrics_unavailable", and the supervisor runs on without metrics.
  std::unique_ptr<metrics::ServiceMetrics> metrics_;
  std::unique_ptr<Vda5050Publisher> vda_;  // null unless "vda5050" is enabled
  std::unique_ptr<HttpApi> http_;          // declared last: stopped first
  std::vector<StoredPose> pending_poses_;
  std::vector<StoredHealth> pending_health_;
  // For GET /readyz, written by the main loop and read by HTTP threads.
  std::atomic<double> last_step_{0.0};       // steady seconds of the newest loop step (DDS taken)
  std::atomic<bool> history_written_{true};  // the newest history flush succeeded
  std::vector<ReadinessCheck> Readiness() const;
  double next_flush_ = 0, next_prune_ = 0, next_snapshot_ = 0, next_health_ = 0, next_alerts_ = 0;
};

}  // namespace fleetloc::fleet_supervisor
