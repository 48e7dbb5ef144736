// Map server: mosaic announcement, tile serving loop and health.
#include "map_server/map_server.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "transport/mosaic_messages.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::map_server {

namespace topics = transport::topics;
using transport::Topic;

namespace {

constexpr dds_attach_t kTileRequests = 1;

// Moves a successful Result into *out; otherwise returns its Status.
template <typename T>
Status Assign(Result<T> result, std::unique_ptr<T>* out) {
  if (!result.ok()) return result.status();
  *out = std::make_unique<T>(std::move(result).value());
  return Status::Ok();
}

std::vector<std::string> AllCounterNames() {
  std::vector<std::string> names = TileService::CounterNames();
  names.push_back("rejected_wire_version");
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
  owned_ = config_.owned_tiles.value_or(mosaic::TileOwnership::All(store_->layout()));
  FLEETLOC_RETURN_IF_ERROR(Assign(
      transport::Participant::Create(config_.domain_id, {"", config_.dds_config_path}),
      &participant_));
  const transport::Participant& p = *participant_;
  FLEETLOC_RETURN_IF_ERROR(Assign(Topic<fleetloc_MosaicInfo>::Create(p, topics::kMosaicInfo), &info_topic_));
  FLEETLOC_RETURN_IF_ERROR(Assign(Topic<fleetloc_TileRequest>::Create(p, topics::kTileRequest), &request_topic_));
  FLEETLOC_RETURN_IF_ERROR(Assign(Topic<fleetloc_Tile>::Create(p, topics::kTile), &tile_topic_));
  FLEETLOC_RETURN_IF_ERROR(Assign(Topic<fleetloc_PatchAck>::Create(p, topics::kPatchAck), &ack_topic_));
  FLEETLOC_RETURN_IF_ERROR(Assign(Topic<fleetloc_ServiceHealth>::Create(p, topics::kServiceHealth), &health_topic_));
  FLEETLOC_RETURN_IF_ERROR(Assign(transport::Writer<fleetloc_MosaicInfo>::Create(
                                      p.get(), *info_topic_, transport::DurableStateQos()),
                                  &info_writer_));
  FLEETLOC_RETURN_IF_ERROR(Assign(
      transport::Writer<fleetloc_ServiceHealth>::Create(
          p.get(), *health_topic_, transport::PeriodicStateQos(3 * config_.health_period_s, 
                                                               5 * config_.health_period_s)),
      &health_writer_));
  FLEETLOC_RETURN_IF_ERROR(Assign(transport::Reader<fleetloc_TileRequest>::Create(
                                      p.get(), *request_topic_, transport::CommandQos()),
                                  &request_reader_));
  FLEETLOC_RETURN_IF_ERROR(Assign(transport::WaitSet::Create(p), &waitset_));
  FLEETLOC_RETURN_IF_ERROR(waitset_->AttachReader(request_reader_->get(), kTileRequests));
  channels_ = std::make_unique<VehicleChannels>(p, *tile_topic_, *ack_topic_,
                                                static_cast<size_t>(config_.max_vehicles));
  tiles_ = std::make_unique<TileService>(store_.get(), owned_, channels_.get(), &counters_,
                                         config_.max_tiles_per_request,
                                         static_cast<size_t>(config_.tile_cache_mb) << 20);
  return PublishMosaicInfo();
}

Status MapServer::PublishMosaicInfo() {
  const mosaic::MosaicLayout layout = store_->layout();
  spdlog::info("serving mosaic {} version {} ({}x{} px, {} levels) on domain {}",
               layout.mosaic_id, layout.version, layout.width_px, layout.height_px,
               layout.levels, config_.domain_id);
  return info_writer_->Write(transport::ToIdl(layout, config_.server_id, owned_));
}

Status MapServer::PublishHealth() {
  fleetloc_ServiceHealth health{};
  health.wire_version = fleetloc_WIRE_VERSION;
  transport::SetBounded(health.service_id, config_.server_id);
  transport::SetBounded(health.kind, "map_server");
  health.stamp = transport::NowStamp();
  std::vector<fleetloc_Counter> counters;
  for (const auto& [name, value] : counters_.Snapshot()) {
    fleetloc_Counter counter{};
    transport::SetBounded(counter.name, name);
    counter.value = value;
    counters.push_back(counter);
  }
  health.counters._buffer = counters.data();
  health.counters._length = health.counters._maximum = static_cast<uint32_t>(counters.size());
  fleetloc_HealthIssue issue{};
  const uint64_t rejected = counters_.TotalRejected();
  const uint64_t read_errors = counters_.Get("tile_read_errors");
  health.level = fleetloc_HEALTH_OK;
  if (read_errors > reported_read_errors_ || rejected > reported_rejected_) {
    health.level = read_errors > reported_read_errors_ ? fleetloc_HEALTH_ERROR : fleetloc_HEALTH_WARN;
    transport::SetBounded(issue.name, read_errors > reported_read_errors_ ? "tile_read_errors"
                                                                     : "rejected_input");
    issue.level = health.level;
    transport::SetBounded(issue.message, counters_.last_error());
    health.issues._buffer = &issue;
    health.issues._length = health.issues._maximum = 1;
  }
  reported_rejected_ = rejected, reported_read_errors_ = read_errors;
  return health_writer_->Write(health);
}

Status MapServer::ServeOnce() {
  Result<std::vector<dds_attach_t>> woke = waitset_->Wait(0.05);
  if (!woke.ok()) return woke.status();
  Result<int> taken = request_reader_->TakeAll(
      [this](const fleetloc_TileRequest& request, const dds_sample_info_t&) {
        tiles_->Receive(request);
      });
  if (!taken.ok()) return taken.status();
  tiles_->AnswerPending();
  return Status::Ok();
}

Status MapServer::Run(const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration<double>(config_.health_period_s);
  auto next_health = Clock::now();
  while (!stop.load()) {
    if (Status served = ServeOnce(); !served.ok()) spdlog::error("{}", served.message());
    if (Clock::now() >= next_health) {
      if (Status sent = PublishHealth(); !sent.ok()) spdlog::warn("{}", sent.message());
      next_health += std::chrono::duration_cast<Clock::duration>(period);
    }
  }
  spdlog::info("stopping: {} tiles served, {} inputs rejected", counters_.Get("tiles_served"),
               counters_.TotalRejected());
  return Status::Ok();
}

}  // namespace fleetloc::map_server
