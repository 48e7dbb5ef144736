// Map server: mosaic announcement, tile serving loop and health.
#include "map_server/map_server.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "map_server/server_metrics.h"
#include "runtime/service_notify.h"
#include "transport/mosaic_messages.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::map_server {

namespace topics = transport::topics;
using transport::Topic;

namespace {

constexpr dds_attach_t kTileRequests = 1;
constexpr dds_attach_t kPatches = 2;
constexpr dds_attach_t kRemapCommands = 3;

// A vehicle's request or patch whose vehicle_id is not the partition it was written in
// (transport/vehicle_streams.h).
constexpr const char* kRejectedPartition = "rejected_vehicle_partition";

std::vector<std::string> AllCounterNames() {
  std::vector<std::string> names = TileService::CounterNames();
  names.emplace_back(kRejectedPartition);
  for (const char* name : {"tile_rows_pruned", "patches_pruned", "prune_errors"})
    names.emplace_back(name);
  for (const auto& more : {PatchService::CounterNames(), RemapService::CounterNames(),
                           PlaceIndexService::CounterNames()}) {
    names.insert(names.end(), more.begin(), more.end());
  }
  return names;
}

}  // namespace

MapServer::MapServer(const MapServerConfig& config)
    : config_(config), counters_(AllCounterNames()) {}

MapServer::~MapServer() = default;

Result<std::unique_ptr<MapServer>> MapServer::Create(const MapServerConfig& config) {
  FLEETLOC_RETURN_IF_ERROR(Validate(config));
  std::unique_ptr<MapServer> server(new MapServer(config));
  FLEETLOC_RETURN_IF_ERROR(server->Open());
  return server;
}

Status MapServer::Open() {
  auto store = mosaic::TileStore::Open(config_.mosaic_path, mosaic::OpenMode::kReadWrite);
  if (!store.ok()) return store.status();
  store_ = std::move(store).value();
  auto patches = mosaic::PatchStore::Open(config_.mosaic_path);
  if (!patches.ok()) return patches.status();
  patches_ = std::move(patches).value();
  auto standing = mosaic_upkeep::VehicleStandingStore::Open(config_.mosaic_path);
  if (!standing.ok()) return standing.status();
  standing_ = std::move(standing).value();
  owned_ = config_.owned_tiles.value_or(mosaic::TileOwnership::All(store_->layout()));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Participant::Create(config_.domain_id, {"", config_.dds_config_path}),
               &participant_));
  FLEETLOC_RETURN_IF_ERROR(OpenTopics());
  FLEETLOC_RETURN_IF_ERROR(OpenServices());
  metrics_ = std::make_unique<metrics::ServiceMetrics>(config_.metrics, "map_server");
  return PublishMosaicInfo();
}

Status MapServer::OpenTopics() {
  using transport::Reader;
  using transport::VehicleStreamReader;
  using transport::Writer;
  const transport::Participant& p = *participant_;
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_MosaicInfo>::Create(p, topics::kMosaicInfo), &info_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_TileRequest>::Create(p, topics::kTileRequest), &request_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(Topic<fleetloc_Tile>::Create(p, topics::kTile), &tile_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_PatchAck>::Create(p, topics::kPatchAck), &ack_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_ServiceHealth>::Create(p, topics::kServiceHealth), &health_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      Topic<fleetloc_PatchObservation>::Create(p, topics::kPatchObservation), &patch_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_RemapCommand>::Create(p, topics::kRemapCommand), &remap_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_RemapStatus>::Create(p, topics::kRemapStatus), &remap_status_topic_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Topic<fleetloc_TileUpdate>::Create(p, topics::kTileUpdate), &update_topic_));
  const double period = config_.health_period_s;
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      Writer<fleetloc_MosaicInfo>::Create(p.get(), *info_topic_, transport::DurableStateQos()),
      &info_writer_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Writer<fleetloc_ServiceHealth>::Create(
                   p.get(), *health_topic_, transport::PeriodicStateQos(3 * period, 5 * period)),
               &health_writer_));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(Writer<fleetloc_RemapStatus>::Create(p.get(), *remap_status_topic_,
                                                    transport::DurableStateQos()),
               &remap_status_writer_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      Writer<fleetloc_TileUpdate>::Create(p.get(), *update_topic_, transport::DurableStateQos(32)),
      &update_writer_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(VehicleStreamReader<fleetloc_TileRequest>::Create(
                                        p, *request_topic_, transport::CommandQos()),
                                    &request_reader_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(VehicleStreamReader<fleetloc_PatchObservation>::Create(
                                        p, *patch_topic_, transport::BulkQos()),
                                    &patch_reader_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      Reader<fleetloc_RemapCommand>::Create(p.get(), *remap_topic_, transport::CommandQos()),
      &remap_reader_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::WaitSet::Create(p), &waitset_));
  FLEETLOC_RETURN_IF_ERROR(waitset_->AttachReader(request_reader_->get(), kTileRequests));
  FLEETLOC_RETURN_IF_ERROR(waitset_->AttachReader(patch_reader_->get(), kPatches));
  return waitset_->AttachReader(remap_reader_->get(), kRemapCommands);
}

Status MapServer::OpenServices() {
  channels_ =
      std::make_unique<VehicleChannels>(*participant_, config_.server_id, *tile_topic_, *ack_topic_,
                                        static_cast<size_t>(config_.max_vehicles));
  tiles_ = std::make_unique<TileService>(store_.get(), owned_, channels_.get(), &counters_,
                                         config_.max_tiles_per_request,
                                         static_cast<size_t>(config_.tile_cache_mb) << 20);
  PatchIntake intake = config_.intake;
  intake.limits = {config_.max_patch_bytes, config_.max_patch_side_px};
  patch_service_ = std::make_unique<PatchService>(patches_.get(), store_.get(), standing_.get(),
                                                  intake, channels_.get(), &counters_);
  remaps_ = std::make_unique<RemapService>(
      config_.server_id,
      [this](const RemapJob& job, const RemapProgressFn& progress,
             const std::atomic<bool>& cancel) { return RunRemapJob(job, progress, cancel); },
      remap_status_writer_.get(), &counters_,
      Maintenance{config_.retention.prune_period_s, [this] { Prune(); }});
  if (!config_.serve_place_index) return Status::Ok();
  auto publisher = transport::PlaceIndexPublisher::Create(*participant_, config_.server_id);
  if (!publisher.ok()) return publisher.status();
  place_index_publisher_ = std::move(publisher).value();
  place_index_ = std::make_unique<PlaceIndexService>(
      config_.mosaic_path, place_index_publisher_.get(), &counters_, config_.self_similarity_grid);
  place_index_->RequestCurrent();
  return Status::Ok();
}

Result<RemapOutcome> MapServer::RunRemapJob(const RemapJob& job, const RemapProgressFn& progress,
                                            const std::atomic<bool>& cancel) {
  // The job writes through its own connections, so the DDS loop keeps serving the committed
  // version from store_ meanwhile.
  Result<mosaic_upkeep::RemapStores> stores =
      mosaic_upkeep::OpenRemapStores(config_.mosaic_path, mosaic::OpenMode::kReadWrite);
  if (!stores.ok()) return stores.status();
  const mosaic_upkeep::RemapRequest request{
      {job.x_min, job.y_min, job.x_max, job.y_max},
      job.replace ? mosaic_upkeep::RemapMode::kReplace : mosaic_upkeep::RemapMode::kBlend,
      config_.remap_policy};
  // Fault injection for the tests only (tests/map_server_fault_test.cpp): with
  // FLEETLOC_FAILPOINT_COMMIT_PAUSE_S set, the job reports and then pauses after writing its first
  // tile into the uncommitted version, so a test can kill the server inside the commit.
  const char* pause = std::getenv("FLEETLOC_FAILPOINT_COMMIT_PAUSE_S");
  Result<mosaic_upkeep::RemapResult> result = mosaic_upkeep::RunRemap(
      *stores->tiles, *stores->patches, *stores->standing, request,
      [&](const mosaic_upkeep::RemapProgress& p) {
        const double fraction = p.total > 0 ? static_cast<double>(p.done) / p.total : 0.0;
        if (pause != nullptr && p.phase == "commit" && p.done == 1 && p.total > 1) {
          std::this_thread::sleep_for(std::chrono::milliseconds(250));  // past the report throttle
          progress(p.phase, fraction);
          std::this_thread::sleep_for(std::chrono::duration<double>(std::atof(pause)));
        }
        progress(p.phase, fraction);
      },
      &cancel);
  if (!result.ok()) return result.status();
  return RemapOutcome{result->new_version,      result->changed_tiles,
                      result->patches_folded,   result->patches_rejected,
                      result->patches_held,     mosaic_upkeep::RemapSummary(*result),
                      result->newly_quarantined};
}

void MapServer::Prune() {
  const double now =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  Result<mosaic::PruneResult> pruned =
      mosaic::PruneMosaic(config_.mosaic_path, config_.retention.policy, now);
  if (!pruned.ok()) return counters_.Reject("prune_errors", pruned.status().message());
  counters_.Add("tile_rows_pruned", static_cast<uint64_t>(pruned->tile_rows_deleted));
  counters_.Add("patches_pruned", static_cast<uint64_t>(pruned->patches_deleted));
  if (pruned->tile_rows_deleted > 0 || pruned->patches_deleted > 0) {
    spdlog::info("pruned {} tile rows older than version {} and {} patches ({} MB)",
                 pruned->tile_rows_deleted, pruned->oldest_version_kept, pruned->patches_deleted,
                 pruned->patch_bytes_deleted >> 20);
  }
  patch_service_->RefreshUsage();
}

Status MapServer::AnnounceFinishedJobs() {
  for (const RemapOutcome& outcome : remaps_->TakeFinished()) {
    Result<long long> version = store_->Refresh();
    if (!version.ok()) return version.status();
    FLEETLOC_RETURN_IF_ERROR(AnnounceVersion(outcome.new_version, outcome.changed_tiles));
  }
  return Status::Ok();
}

Status MapServer::AnnounceVersionsCommittedElsewhere() {
  const auto now = std::chrono::steady_clock::now();
  if (now < next_version_check_) return Status::Ok();
  next_version_check_ = now + std::chrono::milliseconds(500);
  const long long served = store_->version();
  Result<long long> committed = store_->Refresh();
  if (!committed.ok()) return committed.status();
  if (*committed <= served || *committed <= announced_version_) return Status::Ok();
  Result<std::vector<mosaic::TileKey>> changed = store_->TilesChangedAfter(served);
  if (!changed.ok()) return changed.status();
  spdlog::info(
      "mosaic version {} was committed by another writer (e.g. fleetctl mosaic rollback): "
      "{} tiles changed since version {}",
      *committed, changed->size(), served);
  return AnnounceVersion(*committed, *changed);
}

Status MapServer::AnnounceVersion(long long version, const std::vector<mosaic::TileKey>& changed) {
  if (version <= announced_version_) return Status::Ok();
  announced_version_ = version;
  tiles_->DropCache();
  std::vector<fleetloc_TileAddress> addresses;
  addresses.reserve(changed.size());
  for (const mosaic::TileKey& key : changed) addresses.push_back(transport::ToIdl(key));
  fleetloc_TileUpdate update{};
  update.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  transport::SetBounded(update.server_id, config_.server_id);
  transport::SetBounded(update.mosaic_id, store_->layout().mosaic_id);
  update.version = version;
  update.tiles._buffer = addresses.data();
  update.tiles._length = update.tiles._maximum = static_cast<uint32_t>(addresses.size());
  FLEETLOC_RETURN_IF_ERROR(update_writer_->Write(update));
  FLEETLOC_RETURN_IF_ERROR(PublishMosaicInfo());
  if (place_index_) place_index_->RequestCurrent();
  return Status::Ok();
}

Status MapServer::PublishMosaicInfo() {
  const mosaic::MosaicLayout layout = store_->layout();
  spdlog::info("serving mosaic {} version {} ({}x{} px, {} levels) on domain {}", layout.mosaic_id,
               layout.version, layout.width_px, layout.height_px, layout.levels, config_.domain_id);
  return info_writer_->Write(transport::ToIdl(layout, config_.server_id, owned_));
}

std::optional<transport::ServiceHealthReport::Issue> MapServer::HealthIssue() {
  const uint64_t rejected = counters_.TotalRejected();
  const uint64_t read_errors = counters_.Get("tile_read_errors");
  const bool new_read_errors = read_errors > reported_read_errors_;
  const bool new_rejects = rejected > reported_rejected_;
  reported_rejected_ = rejected;
  reported_read_errors_ = read_errors;
  if (new_read_errors) return {{"tile_read_errors", fleetloc_HEALTH_ERROR, counters_.last_error()}};
  // Quarantined vehicles stay an issue until a maintainer releases them (read from the file each
  // time, so a release by `fleetctl mosaic vehicles --release` shows at once).
  Result<std::map<std::string, mapping::VehicleStanding>> standings = standing_->All();
  std::string quarantined;
  if (standings.ok()) {
    for (const auto& [vehicle, s] : *standings) {
      if (s.quarantined)
        quarantined += (quarantined.empty() ? "" : "; ") + vehicle + ": " + s.reason;
    }
  }
  if (!quarantined.empty()) return {{"vehicle_quarantined", fleetloc_HEALTH_WARN, quarantined}};
  if (new_rejects) return {{"rejected_input", fleetloc_HEALTH_WARN, counters_.last_error()}};
  if (!metrics_->error().empty())
    return {{"metrics_unavailable", fleetloc_HEALTH_WARN, metrics_->error()}};
  // The floor repeats itself: a vehicle lost there is refused as ambiguous until it moves on.
  if (place_index_) {
    if (std::optional<std::string> similar = place_index_->self_similarity_warning())
      return {{"self_similar_floor", fleetloc_HEALTH_WARN, *similar}};
  }
  return std::nullopt;
}

Status MapServer::PublishHealth() {
  transport::ServiceHealthReport report{config_.server_id, "map_server", HealthIssue(),
                                        counters_.Snapshot()};
  return transport::WriteServiceHealth(*health_writer_, report);
}

void MapServer::RefreshMetrics() {
  MapServerMetricsInput in{counters_.Snapshot(), tiles_->reply_latency().Snapshot(),
                           tiles_->cache_stats(), tiles_->pending(), store_->layout().version};
  metrics::FamilyBuilder b(kMapServerMetricPrefix, {{"service_id", config_.server_id}});
  AddMapServerFamilies(in, &b);
  metrics_->Publish(b.Take());
}

Status MapServer::ServeOnce() {
  Result<std::vector<dds_attach_t>> woke = waitset_->Wait(0.05);
  if (!woke.ok()) return woke.status();
  auto rejected = [this](const char* what) {
    return [this, what](const std::string& message) {
      counters_.Reject(kRejectedPartition, std::string(what) + ": " + message);
    };
  };
  Result<int> taken =
      request_reader_->TakeAll([this](const fleetloc_TileRequest& request,
                                      const dds_sample_info_t&) { tiles_->Receive(request); },
                               rejected("tile request"));
  if (!taken.ok()) return taken.status();
  taken =
      patch_reader_->TakeAll([this](const fleetloc_PatchObservation& patch,
                                    const dds_sample_info_t&) { patch_service_->Receive(patch); },
                             rejected("patch"));
  if (!taken.ok()) return taken.status();
  const mosaic::MosaicLayout layout = store_->layout();
  taken =
      remap_reader_->TakeAll([&](const fleetloc_RemapCommand& command, const dds_sample_info_t&) {
        remaps_->Receive(command, layout);
      });
  if (!taken.ok()) return taken.status();
  tiles_->AnswerPending();
  patch_service_->FlushAcks();
  if (place_index_) place_index_->PublishReady();
  FLEETLOC_RETURN_IF_ERROR(AnnounceFinishedJobs());
  return AnnounceVersionsCommittedElsewhere();
}

Status MapServer::Run(const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration<double>(config_.health_period_s);
  auto next_health = Clock::now();
  while (!stop.load()) {
    runtime::NotifyServiceAlive();  // READY=1, then the systemd watchdog
    if (Status served = ServeOnce(); !served.ok()) spdlog::error("{}", served.message());
    if (metrics_->Due()) RefreshMetrics();
    if (Clock::now() >= next_health) {
      if (Status sent = PublishHealth(); !sent.ok()) spdlog::warn("{}", sent.message());
      next_health += std::chrono::duration_cast<Clock::duration>(period);
    }
  }
  runtime::NotifyServiceStopping();
  spdlog::info("stopping: {} tiles served, {} inputs rejected", counters_.Get("tiles_served"),
               counters_.TotalRejected());
  return Status::Ok();
}

}  // namespace fleetloc::map_server
