// The map server: owns the one shared mosaic (SQLite), announces it (MosaicInfo, durable),
// answers tile requests into each vehicle's partition, collects and acknowledges patches, runs
// re-mapping jobs (announcing changed tiles with TileUpdate), serves the place index of each
// mosaic version for global relocalization (PlaceIndexChunk, durable), and reports its health
// (ServiceHealth). One thread runs the DDS loop, one the re-mapping jobs, one builds place
// indexes; Run() returns when the stop flag is set.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>

#include "map_server/map_server_config.h"
#include "map_server/patch_service.h"
#include "map_server/place_index_service.h"
#include "map_server/remap_service.h"
#include "map_server/server_counters.h"
#include "map_server/tile_service.h"
#include "map_server/vehicle_channels.h"
#include "metrics/metrics_exporter.h"
#include "mosaic/mosaic_retention.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_store.h"
#include "mosaic_upkeep/remap_job.h"
#include "mosaic_upkeep/vehicle_standing_store.h"
#include "transport/service_health_messages.h"
#include "transport/typed_io.h"
#include "transport/vehicle_streams.h"
#include "transport/waitset.h"

namespace fleetloc::map_server {

class MapServer {
 public:
  // Opens the mosaic and every DDS entity. NotFound/InvalidInput for a missing or foreign
  // mosaic file; Internal for DDS failures (named).
  static Result<std::unique_ptr<MapServer>> Create(const MapServerConfig& config);
  ~MapServer();

  // Serves until `stop` becomes true (checked every 100 ms).
  Status Run(const std::atomic<bool>& stop);

  const ServerCounters& counters() const { return counters_; }
  int metrics_port() const { return metrics_ ? metrics_->port() : 0; }

 private:
  explicit MapServer(const MapServerConfig& config);
  Status Open();
  Status PublishMosaicInfo();
  Status PublishHealth();
  void RefreshMetrics();
  Status ServeOnce();
  Status OpenTopics();
  Status OpenServices();
  // Announces the versions re-mapping jobs committed: TileUpdate, then the new MosaicInfo.
  Status AnnounceFinishedJobs();
  // Every 0.5 s: a version another writer committed to the file (`fleetctl mosaic rollback`, a
  // tool) is served and announced the same way, with the tiles changed since the served one.
  Status AnnounceVersionsCommittedElsewhere();
  Status AnnounceVersion(long long version, const std::vector<mosaic::TileKey>& changed);
  Result<RemapOutcome> RunRemapJob(const RemapJob& job, const RemapProgressFn& progress,
                                   const std::atomic<bool>& cancel);
  // Retention (mosaic/mosaic_retention.h), run by the re-mapping thread between jobs.
  void Prune();

  MapServerConfig config_;
  long long announced_version_ = 0;  // the newest version announced (DDS loop only)
  std::chrono::steady_clock::time_point next_version_check_{};
  ServerCounters counters_;
  std::unique_ptr<mosaic::TileStore> store_;
  std::unique_ptr<mosaic::PatchStore> patches_;
  std::unique_ptr<mosaic_upkeep::VehicleStandingStore> standing_;
  mosaic::TileOwnership owned_;
  std::unique_ptr<transport::Participant> participant_;
  std::unique_ptr<transport::Topic<fleetloc_MosaicInfo>> info_topic_;
  std::unique_ptr<transport::Topic<fleetloc_TileRequest>> request_topic_;
  std::unique_ptr<transport::Topic<fleetloc_Tile>> tile_topic_;
  std::unique_ptr<transport::Topic<fleetloc_PatchAck>> ack_topic_;
  std::unique_ptr<transport::Topic<fleetloc_ServiceHealth>> health_topic_;
  std::unique_ptr<transport::Topic<fleetloc_PatchObservation>> patch_topic_;
  std::unique_ptr<transport::Topic<fleetloc_RemapCommand>> remap_topic_;
  std::unique_ptr<transport::Topic<fleetloc_RemapStatus>> remap_status_topic_;
  std::unique_ptr<transport::Topic<fleetloc_TileUpdate>> update_topic_;
  std::unique_ptr<transport::Writer<fleetloc_MosaicInfo>> info_writer_;
  std::unique_ptr<transport::Writer<fleetloc_ServiceHealth>> health_writer_;
  std::unique_ptr<transport::Writer<fleetloc_RemapStatus>> remap_status_writer_;
  std::unique_ptr<transport::Writer<fleetloc_TileUpdate>> update_writer_;
  std::unique_ptr<transport::VehicleStreamReader<fleetloc_TileRequest>> request_reader_;
  std::unique_ptr<transport::VehicleStreamReader<fleetloc_PatchObservation>> patch_reader_;
  std::unique_ptr<transport::Reader<fleetloc_RemapCommand>> remap_reader_;
  std::unique_ptr<transport::WaitSet> waitset_;
  std::unique_ptr<VehicleChannels> channels_;
  std::unique_ptr<TileService> tiles_;
  std::unique_ptr<PatchService> patch_service_;
  std::unique_ptr<transport::PlaceIndexPublisher> place_index_publisher_;
  std::unique_ptr<PlaceIndexService> place_index_;  // null unless config_.serve_place_index
  // /metrics (config "metrics"); a port that cannot be bound is the health issue
  // "metrics_unavailable", and the server runs on without metrics.
  std::unique_ptr<metrics::ServiceMetrics> metrics_;
  std::unique_ptr<RemapService> remaps_;  // declared last: its worker stops first
  // The health report's issue, worst first: tile read errors, quarantined vehicles, rejects.
  std::optional<transport::ServiceHealthReport::Issue> HealthIssue();
  uint64_t reported_rejected_ = 0;  // counts in the last health report
  uint64_t reported_read_errors_ = 0;
};

}  // namespace fleetloc::map_server
