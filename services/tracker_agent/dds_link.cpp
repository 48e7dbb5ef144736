// DdsLink: the agent's DDS entities, the mosaic's tiles from the map servers, and what it
// publishes (VehiclePose, VehicleHealth, the ROS 2 bridge's topics).
#include "tracker_agent/dds_link.h"

#include <spdlog/spdlog.h>

#include <thread>

#include "camera_io/camera_source.h"
#include "tracking/camera_scale_check.h"
#include "transport/mosaic_messages.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::tracker_agent {

namespace topics = transport::topics;

namespace {

// Moves a successful Result's object into *out; otherwise returns its Status.
template <typename T>
Status TakeInto(Result<std::unique_ptr<T>> result, std::unique_ptr<T>* out) {
  if (!result.ok()) return result.status();
  *out = std::move(result).value();
  return Status::Ok();
}

}  // namespace

Result<std::unique_ptr<DdsLink>> DdsLink::Create(const AgentConfig& config,
                                                 const geometry::CameraModel& camera,
                                                 AgentHealth* health) {
  std::unique_ptr<DdsLink> link(new DdsLink(config, health));
  FLEETLOC_RETURN_IF_ERROR(link->OpenStreams());
  spdlog::info("waiting up to {} s for a map server on domain {}", config.mosaic_wait_s,
               config.domain_id);
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(config.mosaic_wait_s));
  FLEETLOC_RETURN_IF_ERROR(link->AwaitMosaic(deadline));
  FLEETLOC_RETURN_IF_ERROR(
      tracking::CheckCameraResolution(camera.resolution_m, link->layout_.geo.resolution,
                                      "vehicle " + config.vehicle_id + "'s camera"));
  FLEETLOC_RETURN_IF_ERROR(link->OpenTiles(deadline));
  FLEETLOC_RETURN_IF_ERROR(link->OpenRelocalizer(camera));
  return link;
}

Status DdsLink::OpenRosBridge() {
  if (!config_.ros.enabled) return Status::Ok();
  return TakeInto(RosBridge::Create(*participant_, config_.ros, config_.vehicle_id), &ros_);
}

Status DdsLink::OpenStreams() {
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Participant::Create(config_.domain_id, {"", config_.dds_config_path}),
               &participant_));
  const transport::Participant& p = *participant_;
  FLEETLOC_RETURN_IF_ERROR(TakeInto(transport::TileClient::Create(p, config_.vehicle_id), &tiles_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<fleetloc_VehiclePose>::Create(p, topics::kVehiclePose), &pose_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<fleetloc_VehicleHealth>::Create(p, topics::kVehicleHealth), &health_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<fleetloc_TileUpdate>::Create(p, topics::kTileUpdate), &update_topic_));
  const std::string& id = config_.vehicle_id;  // its streams go in its own partition
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::VehicleStreamWriter<fleetloc_VehiclePose>::Create(
                                        p, id, *pose_topic_, transport::PoseStreamQos()),
                                    &pose_writer_));
  const double period = config_.health_period_s;
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::VehicleStreamWriter<fleetloc_VehicleHealth>::Create(
                   p, id, *health_topic_, transport::PeriodicStateQos(3 * period, 5 * period)),
               &health_writer_));
  return AssignTo(transport::Reader<fleetloc_TileUpdate>::Create(p.get(), *update_topic_,
                                                                 transport::DurableStateQos(32)),
                  &update_reader_);
}

Status DdsLink::AwaitMosaic(std::chrono::steady_clock::time_point deadline) {
  std::optional<fleetloc_MosaicInfo> info;
  while (!(info = tiles_->LatestMosaicInfo()) || !tiles_->RequestsMatched()) {
    if (std::chrono::steady_clock::now() > deadline) {
      return Internal("no map server announced a mosaic on domain " +
                      std::to_string(config_.domain_id));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  Result<mosaic::MosaicLayout> layout = transport::LayoutFromIdl(*info);
  if (!layout.ok()) return layout.status();
  layout_ = *layout;
  spdlog::info("mosaic {} version {} from '{}'", layout_.mosaic_id, layout_.version,
               transport::GetBounded(info->server_id));
  return Status::Ok();
}

Status DdsLink::OpenTiles(std::chrono::steady_clock::time_point deadline) {
  FLEETLOC_RETURN_IF_ERROR(TakeInto(
      MapServerDirectory::Create(*participant_, tiles_.get(), layout_,
                                 std::chrono::duration<double>(config_.map_server_timeout_s)),
      &map_servers_));
  WaitForTileCoverage(deadline);
  loader_ = std::make_unique<transport::DdsTileLoader>(
      tiles_.get(), layout_.mosaic_id, layout_.tile_size_px,
      std::chrono::milliseconds(config_.tile_timeout_ms));
  loader_->SetReachability(
      [this](const mosaic::TileKey& key) { return map_servers_->Reachable(key); });
  loader_->SetRoundTripObserver([this](double seconds) { tile_round_trip_.Observe(seconds); });
  tile_cache_ =
      std::make_shared<mosaic::TileCache>(static_cast<size_t>(config_.tile_cache_mb) << 20);
  view_ = std::make_unique<mosaic::MosaicView>(layout_, loader_->AsTileLoader(), tile_cache_);
  return Status::Ok();
}

void DdsLink::WaitForTileCoverage(std::chrono::steady_clock::time_point deadline) {
  // With the mosaic split across map servers, the other servers' MosaicInfos may come a moment
  // after the first: wait for them (bounded) so no region starts out unreachable.
  long long uncovered = 0;
  while ((uncovered = map_servers_->UncoveredTiles()) > 0 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    map_servers_->Poll();
  }
  if (uncovered > 0) {
    spdlog::warn("{} level-0 tiles of mosaic {} have no map server: they are blank to this vehicle",
                 uncovered, layout_.mosaic_id);
  }
}

Status DdsLink::OpenRelocalizer(const geometry::CameraModel& camera) {
  relocalization::RelocalizerOptions options;
  options.trajectory_frames = config_.relocalize_trajectory_frames;
  options.dense.threads = options.dense_fine.threads = config_.relocalize_threads;
  return TakeInto(
      AgentRelocalizer::Create(*participant_, layout_.mosaic_id, view_.get(), camera, options),
      &relocalizer_);
}

void DdsLink::WaitForPlaceIndex() {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(config_.mosaic_wait_s));
  while (!relocalizer_->ready() && std::chrono::steady_clock::now() < deadline) {
    relocalizer_->Poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!relocalizer_->ready()) {
    spdlog::warn("no place index after {} s: frames are dropped until one is loaded",
                 config_.mosaic_wait_s);
  }
}

Status DdsLink::Prefetch(const std::vector<mosaic::TileKey>& keys) {
  return loader_->Prefetch(keys);
}

Result<size_t> DdsLink::DecodeArrived(size_t max_tiles) {
  return loader_->DecodeArrived(max_tiles);
}

bool DdsLink::Settled() const { return loader_->pending() == 0 && loader_->encoded() == 0; }

bool DdsLink::Cached(const mosaic::TileKey& key) const { return tile_cache_->Contains(key); }

void DdsLink::PublishPose(const PoseToPublish& pose) {
  const transport::PoseReport report{config_.vehicle_id, pose.t, pose.base, pose.state,
                                     layout_.version};
  if (Status sent = pose_writer_->Write(transport::ToIdl(report)); !sent.ok()) {
    health_.RecordError(sent.message());
  }
  // The ROS 2 pose topic: poses at frame times and given start poses, not lost ones.
  if (!ros_ || pose.state == tracking::LockState::kLost || pose.origin == PoseOrigin::kOdometry)
    return;
  if (Status sent = ros_->PublishPose(pose.t, pose.base); !sent.ok())
    health_.RecordError(sent.message());
  // The pose of the frame in its cycle (a given start pose has no capture).
  if (pose.origin == PoseOrigin::kFrame && pose.cycle) {
    capture_latency_.Record(pose.cycle->times, pose.cycle->cycle_start, camera_io::HostNow());
  }
}

void DdsLink::PublishMapToOdom(double t, const geometry::Pose2& base_in_map,
                               const geometry::Pose2& base_in_odom) {
  if (Status sent = ros_->PublishMapToOdom(t, base_in_map, base_in_odom); !sent.ok()) {
    health_.RecordError(sent.message());
  }
}

std::optional<transport::RosPoseStamped> DdsLink::TakeInitialPose() {
  return ros_ ? ros_->TakeInitialPose() : std::nullopt;
}

void DdsLink::ApplyTileUpdates(
    const std::function<void(const std::vector<mosaic::TileKey>&)>& drop_from_tracker) {
  (void)update_reader_->TakeAll([&](const fleetloc_TileUpdate& update, const dds_sample_info_t&) {
    if (transport::GetBounded(update.mosaic_id) != layout_.mosaic_id ||
        update.version <= layout_.version)
      return;
    std::vector<mosaic::TileKey> changed;
    for (uint32_t i = 0; i < update.tiles._length; ++i)
      changed.push_back(transport::FromIdl(update.tiles._buffer[i]));
    for (const mosaic::TileKey& key : changed) tile_cache_->Erase(key);
    drop_from_tracker(changed);
    loader_->Invalidate(changed, update.version);
    layout_.version = update.version;
    spdlog::info("mosaic version {}: {} tiles dropped from the caches", update.version,
                 changed.size());
  });
}

void DdsLink::UpdateMapServerReachability() {
  map_servers_->Poll();
  map_server_reachable_ = map_servers_->AllReachable();
}

void DdsLink::PublishHealth(AgentHealth::Inputs in) {
  in.cache = tile_cache_->stats();
  in.loader = loader_->stats();
  in.tiles_pending = loader_->pending();
  in.map_server_reachable = map_server_reachable_;
  in.unreachable_servers = map_servers_->UnreachableNames();
  in.place_index_ready = relocalizer_->ready();
  fleetloc_VehicleHealth health;
  std::vector<fleetloc_HealthIssue> issues;
  health_.Fill(in, &health, &issues);
  if (Status sent = health_writer_->Write(health); !sent.ok()) health_.RecordError(sent.message());
  if (ros_) {
    if (Status sent = ros_->PublishDiagnostics(transport::ToSeconds(health.stamp), health);
        !sent.ok()) {
      health_.RecordError(sent.message());
    }
  }
}

}  // namespace fleetloc::tracker_agent
