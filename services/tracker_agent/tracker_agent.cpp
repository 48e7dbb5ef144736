// Tracker agent: DDS wiring, the frame/odometry/forward-image loop, pose and health publishing.
#include "tracker_agent/tracker_agent.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <limits>
#include <set>
#include <nlohmann/json.hpp>
#include <thread>

#include "camera_io/camera_source.h"
#include "io/file_util.h"
#include "io/service_notify.h"
#include "replay/replay.h"
#include "tracker_agent/agent_metrics.h"
#include "tracking/camera_scale_check.h"
#include "transport/mosaic_messages.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::tracker_agent {

namespace topics = transport::topics;

TrackerAgent::TrackerAgent(const AgentConfig& config, const io::CameraFile& camera,
                           const std::optional<geometry::PoseWithCovariance>& initial)
    : config_(config),
      camera_(camera),
      initial_(initial),
      extrapolation_s_(IsLiveSource(config.source) ? config.live.odometry_extrapolation_s : 0.0),
      odometry_(10.0, extrapolation_s_) {}

Result<std::unique_ptr<TrackerAgent>> TrackerAgent::Create(
    const AgentConfig& config, const io::CameraFile& camera,
    const std::optional<geometry::PoseWithCovariance>& initial,
    const tracking::TrackerOptions& options, std::unique_ptr<AgentPositionUpdate> position_update) {
  FLEETLOC_RETURN_IF_ERROR(Validate(config));
  std::unique_ptr<TrackerAgent> agent(new TrackerAgent(config, camera, initial));
  agent->position_update_ = std::move(position_update);
  FLEETLOC_RETURN_IF_ERROR(agent->Open(options));
  return agent;
}

Status TrackerAgent::Open(const tracking::TrackerOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Participant::Create(config_.domain_id, {"", config_.dds_config_path}), &participant_));
  const transport::Participant& p = *participant_;
  auto client = transport::TileClient::Create(p, config_.vehicle_id);
  if (!client.ok()) return client.status();
  tiles_ = std::move(client).value();
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Topic<fleetloc_VehiclePose>::Create(p, topics::kVehiclePose), &pose_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Topic<fleetloc_VehicleHealth>::Create(p, topics::kVehicleHealth), &health_topic_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Topic<fleetloc_TileUpdate>::Create(p, topics::kTileUpdate), &update_topic_));
  const std::string& id = config_.vehicle_id;  // its streams go in its own partition
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::VehicleStreamWriter<fleetloc_VehiclePose>::Create(p, id, *pose_topic_, transport::PoseStreamQos()), &pose_writer_));
  const double period = config_.health_period_s;
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::VehicleStreamWriter<fleetloc_VehicleHealth>::Create(p, id, *health_topic_, transport::PeriodicStateQos(3 * period, 5 * period)), &health_writer_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::Reader<fleetloc_TileUpdate>::Create(p.get(), *update_topic_, transport::DurableStateQos(32)), &update_reader_));
  spdlog::info("waiting up to {} s for a map server on domain {}", config_.mosaic_wait_s, config_.domain_id);
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(config_.mosaic_wait_s));
  std::optional<fleetloc_MosaicInfo> info;
  while (!(info = tiles_->LatestMosaicInfo()) || !tiles_->RequestsMatched()) {
    if (std::chrono::steady_clock::now() > deadline) {
      return Internal("no map server announced a mosaic on domain " + std::to_string(config_.domain_id));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  Result<mosaic::MosaicLayout> layout = transport::LayoutFromIdl(*info);
  if (!layout.ok()) return layout.status();
  layout_ = *layout;
  spdlog::info("mosaic {} version {} from '{}'", layout_.mosaic_id, layout_.version,
               transport::GetBounded(info->server_id));
  FLEETLOC_RETURN_IF_ERROR(tracking::CheckCameraResolution(camera_.model.resolution_m, layout_.geo.resolution,
                                                           "vehicle " + config_.vehicle_id + "'s camera"));
  auto directory = MapServerDirectory::Create(
      p, tiles_.get(), layout_, std::chrono::duration<double>(config_.map_server_timeout_s));
  if (!directory.ok()) return directory.status();
  map_servers_ = std::move(directory).value();
  WaitForTileCoverage(deadline);
  loader_ = std::make_unique<transport::DdsTileLoader>(
      tiles_.get(), layout_.mosaic_id, layout_.tile_size_px,
      std::chrono::milliseconds(config_.tile_timeout_ms));
  loader_->SetReachability([this](const mosaic::TileKey& key) { return map_servers_->Reachable(key); });
  loader_->SetRoundTripObserver([this](double seconds) { tile_round_trip_.Observe(seconds); });
  tile_cache_ = std::make_shared<mosaic::TileCache>(static_cast<size_t>(config_.tile_cache_mb) << 20);
  view_ = std::make_unique<mosaic::MosaicView>(layout_, loader_->AsTileLoader(), tile_cache_);
  tracker_ = std::make_unique<tracking::MosaicTracker>(options, camera_.model, view_.get());
  propagator_.emplace(options.odometry);
  mapmatch::RelocalizerOptions relocalizer_options;
  relocalizer_options.trajectory_frames = config_.relocalize_trajectory_frames;
  auto relocalizer = AgentRelocalizer::Create(p, layout_.mosaic_id, view_.get(), camera_.model,
                                              relocalizer_options);
  if (!relocalizer.ok()) return relocalizer.status();
  relocalizer_ = std::move(relocalizer).value();
  auto patches = transport::PatchClient::Create(p, config_.vehicle_id);
  if (!patches.ok()) return patches.status();
  patches_ = std::move(patches).value();
  const std::string outbox_path = config_.outbox_path.empty()
                                      ? "fleetloc-outbox-" + config_.vehicle_id + ".db"
                                      : config_.outbox_path;
  auto outbox = PatchOutbox::Open(outbox_path, {config_.outbox_max_patches,
                                               static_cast<long long>(config_.outbox_max_mb) << 20});
  if (!outbox.ok()) return outbox.status();
  outbox_ = std::move(outbox).value();
  rectifier_ = replay::RectifierFor(camera_);
  if (config_.ros.enabled) {
    auto ros = RosBridge::Create(p, config_.ros, config_.vehicle_id);
    if (!ros.ok()) return ros.status();
    ros_ = std::move(ros).value();
  }
  metrics_ = std::make_unique<metrics::ServiceMetrics>(config_.metrics, "tracker_agent");
  if (!metrics_->error().empty()) health_.RecordError(metrics_->error());  // the health's last error
  return Status::Ok();
}

void TrackerAgent::Publish(double t, const geometry::PoseWithCovariance& base,
                           tracking::LockState state, PoseOrigin origin) {
  const transport::PoseReport report{config_.vehicle_id, t, base, state, layout_.version};
  if (Status sent = pose_writer_->Write(transport::ToIdl(report)); !sent.ok()) {
    health_.RecordError(sent.message());
  }
  if (ros_ && state != tracking::LockState::kLost) PublishRos(t, base, origin);
}

void TrackerAgent::OnOdometry(double t, const geometry::Pose2& odom) {
  if (Status added = odometry_.Add({t, odom}); !added.ok()) {
    health_.RecordError("odometry at t=" + std::to_string(t) + ": " + added.message());
    return;  // a NaN or out-of-order sample is dropped, counted in the last error
  }
  latest_odometry_t_ = t;
  CorrectExtrapolatedOdometry();
  PublishDeferredMapToOdom();
  if (restart_pose_) {  // the first sample of a new odometry timeline
    tracker_->Reset(*restart_pose_, odom);
    propagator_->SetAnchor(t, odom, *std::exchange(restart_pose_, std::nullopt));
  }
  if (pending_initial_) ApplyInitialPose(*pending_initial_);
  ProcessReadyFrames();
  if (propagator_->anchored() && t > propagator_->anchor_time()) {
    Publish(t, propagator_->At(t, odom), state_, PoseOrigin::kOdometry);
  }
}

void TrackerAgent::ProcessReadyFrames() {
  while (!waiting_frames_.empty() && FrameReady(waiting_frames_.front().t)) {
    const WaitingFrame frame = std::move(waiting_frames_.front());
    waiting_frames_.pop_front();
    const double span = ExtrapolatedSpan(frame.t);
    extrapolated_frame_t_ = span > 0 ? std::optional<double>(frame.t) : std::nullopt;
    if (span > 0) ++extrapolated_frames_, max_extrapolated_s_ = std::max(max_extrapolated_s_, span);
    if (const std::string gap = InOdometryGap(frame.t); !gap.empty()) {
      spdlog::warn("dropped: {}", gap);
      health_.RecordDroppedFrame(gap);
    } else if (frame.forward) {
      UpdatePosition(frame.t, frame.image);
    } else {
      Track(frame.t, frame.image, frame.times);
    }
  }
}

bool TrackerAgent::Start(double t, const geometry::Pose2& odom) {
  if (!initial_) return false;
  tracker_->Reset(*initial_, odom), started_ = true;
  propagator_->SetAnchor(t, odom, *initial_);
  return true;
}

void TrackerAgent::UpdatePosition(double t, const cv::Mat& image) {
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) {
    return health_.RecordDroppedFrame("forward image at t=" + std::to_string(t) + ": " +
                                      odom.status().message());
  }
  if (!started_) {
    if (!Start(t, *odom)) return;  // nowhere to place its landmarks until a frame relocalizes
    state_ = tracking::LockState::kCoasting;  // odometry only, until a frame or a fit
    health_.RecordLockState(state_);
    Publish(t, *initial_, state_, PoseOrigin::kGiven);
  }
  const geometry::PoseWithCovariance estimate = propagator_->At(t, *odom);
  if (Status added = position_update_->AddImage(t, image, estimate.pose); !added.ok()) {
    return health_.RecordDroppedFrame(added.message());
  }
  // The mosaic tracks to millimetres, the map fit to centimetres: a tracked pose stays.
  const bool use = state_ != tracking::LockState::kTracking;
  const std::optional<geometry::PoseWithCovariance> corrected =
      position_update_->Update(t, estimate, use);
  if (!corrected || !use) return;
  tracker_->Reset(*corrected, *odom);  // the next frame tracks from the corrected pose
  state_ = tracking::LockState::kRelocalized;
  health_.RecordLockState(state_);
  propagator_->SetAnchor(t, *odom, *corrected);
  Publish(t, *corrected, state_);
}

void TrackerAgent::Track(double t, const cv::Mat& frame, const FrameTimes& times) {
  Result<geometry::Pose2> odom = odometry_.At(t);
  if (!odom.ok()) {
    health_.RecordDroppedFrame("frame at t=" + std::to_string(t) + ": " + odom.status().message());
    return;
  }
  if (!started_ && !Start(t, *odom)) {  // where the vehicle is is unknown until a frame relocalizes
    (void)TryRelocalize(t, frame, *odom);
    return;
  }
  if (std::exchange(tracker_warm_up_, std::nullopt)) {
    spdlog::info("warm-up: a frame came before the tiles around the {} were ready ({} "
                 "normalized); it does the rest in its cycle", warm_up_what_, warm_up_tiles_);
  }
  // Ask for the predicted footprint's missing tiles in one batch before the tracker needs them
  // (one round trip instead of one per tile it reads).
  Prefetch(t, propagator_->At(t, *odom).pose);
  // What the loop did not decode yet (a replay runs its frames back to back; live, normally
  // nothing): before the cycle, as the tiles asked for ahead always were.
  DecodeArrivedTiles(std::numeric_limits<size_t>::max());
  if (IsLiveSource(config_.source)) frame_in_cycle_.emplace(times, camera_io::HostNow());
  const auto start = std::chrono::steady_clock::now();
  tracking::FrameResult result = tracker_->Track(frame, t, *odom, ExtrapolatedSpan(t));
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (std::exchange(provisional_, false) && result.state != tracking::LockState::kTracking) {
    spdlog::warn("the relocalized pose did not hold at t={:.3f}: lost again", t);
    result.state = tracking::LockState::kLost;
  }
  coasting_in_a_row_ = result.state == tracking::LockState::kCoasting ? coasting_in_a_row_ + 1 : 0;
  if (result.state == tracking::LockState::kTracking) relocalizer_->ResetTrajectory();
  health_.RecordFrame(result, ms);
  cycle_seconds_.Observe(ms / 1000.0);
  state_ = result.state;
  if (NeedsRelocalization(result) && TryRelocalize(t, frame, *odom)) {
    frame_in_cycle_.reset();  // published there (timed if it was)
    return;
  }
  propagator_->SetAnchor(t, *odom, result.base_in_map);
  Publish(t, result.base_in_map, result.state);
  frame_in_cycle_.reset();  // a lost pose is not timed
  Prefetch(t, result.base_in_map.pose);
  MaybeCollectPatch(t, frame, result);
}

bool TrackerAgent::NeedsRelocalization(const tracking::FrameResult& result) const {
  if (!config_.relocalize_on_lost) return false;
  return result.state == tracking::LockState::kLost ||
         coasting_in_a_row_ >= config_.relocalize_after_coasting_frames;
}

bool TrackerAgent::TryRelocalize(double t, const cv::Mat& frame, const geometry::Pose2& odom) {
  if (!relocalizer_->ready() || t - last_relocalize_t_ < config_.relocalize_interval_s) return false;
  last_relocalize_t_ = t;
  Result<mapmatch::Relocalization> found = relocalizer_->Relocalize(frame, odom);
  if (!found.ok()) {
    health_.RecordError("relocalization: " + found.status().message());
    return false;
  }
  health_.RecordRelocalization(found->found);
  if (!found->found) {
    spdlog::info("relocalization at t={:.3f} found nothing ({:.0f} ms): {}", t,
                 relocalizer_->stats().last_ms, found->reason);
    return false;
  }
  const geometry::PoseWithCovariance& base = found->base_in_map;
  spdlog::info("relocalized at t={:.3f}: ({:.4f}, {:.4f}, {:.2f} deg), {} inliers, {} frame(s), "
               "{:.0f} ms",
               t, base.pose.x, base.pose.y, base.pose.theta * 180.0 / M_PI, found->inliers,
               found->from_trajectory ? found->trajectory_frames : 1,
               relocalizer_->stats().last_ms);
  tracker_->Reset(base, odom);
  started_ = true, provisional_ = true, coasting_in_a_row_ = 0;
  if (position_update_) position_update_->Forget();  // its points were placed before the jump
  state_ = tracking::LockState::kRelocalized;
  propagator_->SetAnchor(t, odom, base);
  Publish(t, base, state_);
  Prefetch(t, base.pose);
  ScheduleTrackerWarmUp(base, "relocalized pose");  // the next frame tracks from it
  return true;
}

void TrackerAgent::Prefetch(double t, const geometry::Pose2& base) {
  // Where the vehicle is and where it will be prefetch_ahead_s from now if it keeps moving as it
  // did over the last prefetch_ahead_s (odometry), with the footprint in between.
  std::vector<geometry::Pose2> along{base};
  const Result<geometry::Pose2> before = odometry_.At(t - config_.prefetch_ahead_s);
  const Result<geometry::Pose2> now = odometry_.At(t);
  if (before.ok() && now.ok()) {
    const geometry::Pose2 step = geometry::Between(*before, *now);
    along.push_back(base * tracking::Interpolate({}, step, 0.5));
    along.push_back(base * step);
  }
  std::set<mosaic::TileKey> keys;
  for (const geometry::Pose2& pose : along) AddFootprintTiles(pose, &keys);
  const std::vector<mosaic::TileKey> missing(keys.begin(), keys.end());
  if (Status asked = loader_->Prefetch(missing); !asked.ok()) health_.RecordError(asked.message());
}

void TrackerAgent::DecodeArrivedTiles(size_t max_tiles) {
  const Result<size_t> encoded = loader_->DecodeArrived(max_tiles);
  if (!encoded.ok()) health_.RecordError(encoded.status().message());
}

void TrackerAgent::AddFootprintTiles(const geometry::Pose2& base, std::set<mosaic::TileKey>* keys) const {
  // The footprint's bounding box grown by the margin, at level 0 and at the coarse levels.
  const geometry::Pose2 camera = base * camera_.model.mount;
  const double reach_m = (std::hypot(camera_.model.width_px, camera_.model.height_px) / 2 +
                          config_.prefetch_margin_px) * layout_.geo.resolution;
  const double u = (camera.x - layout_.geo.origin_x) / layout_.geo.resolution;
  const double v = (layout_.geo.origin_y - camera.y) / layout_.geo.resolution;
  const int r = static_cast<int>(reach_m / layout_.geo.resolution);
  for (int level = 0; level < std::min(layout_.levels, 3); ++level) {
    const cv::Rect box(static_cast<int>(u - r) >> level, static_cast<int>(v - r) >> level,
                       (2 * r) >> level, (2 * r) >> level);
    mosaic::TilesCovering(layout_, level, box).ForEach([&](const mosaic::TileKey& k) {
      if (!tile_cache_->Contains(k)) keys->insert(k);
    });
  }
}

void TrackerAgent::ApplyTileUpdates() {
  (void)update_reader_->TakeAll([&](const fleetloc_TileUpdate& update, const dds_sample_info_t&) {
    if (transport::GetBounded(update.mosaic_id) != layout_.mosaic_id || update.version <= layout_.version) return;
    std::vector<mosaic::TileKey> changed;
    for (uint32_t i = 0; i < update.tiles._length; ++i) changed.push_back(transport::FromIdl(update.tiles._buffer[i]));
    for (const mosaic::TileKey& key : changed) tile_cache_->Erase(key);
    tracker_->DropTiles(changed);
    loader_->Invalidate(changed, update.version);
    layout_.version = update.version;
    spdlog::info("mosaic version {}: {} tiles dropped from the caches", update.version, changed.size());
  });
}

void TrackerAgent::WaitForTileCoverage(std::chrono::steady_clock::time_point deadline) {
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

void TrackerAgent::WaitForPlaceIndex() {
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

void TrackerAgent::UpdateMapServerReachability() {
  map_servers_->Poll();
  map_server_reachable_ = map_servers_->AllReachable();
}

void TrackerAgent::PublishHealth() {
  const Result<long long> outbox = outbox_->Size();
  const Result<long long> dropped = outbox_->Dropped();
  AgentHealth::Inputs in{config_.vehicle_id, tile_cache_->stats(), loader_->stats(), loader_->pending(),
                         outbox.ok() ? static_cast<size_t>(*outbox) : 0, map_server_reachable_,
                         map_servers_->UnreachableNames(),
                         relocalizer_->ready(),
                         position_update_ ? &position_update_->stats() : nullptr,
                         dropped.ok() ? *dropped : 0};
  if (input_ != nullptr) in.input_issues = input_->Issues(), in.input_dropped = input_->DroppedFrames();
  fleetloc_VehicleHealth health;
  std::vector<fleetloc_HealthIssue> issues;
  health_.Fill(in, &health, &issues);
  if (Status sent = health_writer_->Write(health); !sent.ok()) health_.RecordError(sent.message());
  if (ros_) {
    if (Status sent = ros_->PublishDiagnostics(transport::ToSeconds(health.stamp), health); !sent.ok()) {
      health_.RecordError(sent.message());
    }
  }
}

void TrackerAgent::RefreshMetrics() {
  AgentMetricsInput in;
  in.lock_state = state_;
  in.frames = health_.frames();
  in.cycle_seconds = cycle_seconds_.Snapshot();
  in.tile_round_trip_seconds = tile_round_trip_.Snapshot();
  in.cache = tile_cache_->stats();
  in.loader = loader_->stats();
  in.tiles_pending = loader_->pending();
  const Result<long long> outbox = outbox_->Size();
  const Result<long long> dropped = outbox_->Dropped();
  in.outbox_patches = outbox.ok() ? *outbox : 0;
  in.outbox_dropped = dropped.ok() ? *dropped : 0;
  in.map_server_reachable = map_server_reachable_;
  in.relocalization_attempts = relocalizer_->stats().attempts;
  in.relocalization_found = relocalizer_->stats().found;
  metrics::FamilyBuilder b(kAgentMetricPrefix, {{"vehicle_id", config_.vehicle_id}});
  AddAgentFamilies(in, &b);
  metrics_->Publish(b.Take());
}

Status TrackerAgent::WriteSummary() const {
  const RelocalizationStats& reloc = relocalizer_->stats();
  nlohmann::json summary{
      {"vehicle_id", config_.vehicle_id},
      {"frames", health_.frames()},
      {"cycle_ms",
       {{"median", health_.CyclePercentile(50, 10000)},
        {"p95", health_.CyclePercentile(95, 10000)},
        {"p99", health_.CyclePercentile(99, 10000)}}},
      {"tiles",
       {{"requested", loader_->stats().requested},
        {"received", loader_->stats().received},
        {"waited", loader_->stats().waited},
        {"timeouts", loader_->stats().timeouts},
        {"unserved", loader_->stats().unserved},
        {"errors", loader_->stats().errors},
        {"invalidated", loader_->stats().invalidated},
        {"refreshed", loader_->stats().refreshed},
        {"stale", loader_->stats().stale},
        {"reasked", loader_->stats().reasked}}},
      {"relocalization",
       {{"index_version", relocalizer_->index_version()},
        {"indexes_loaded", reloc.indexes_loaded},
        {"indexes_rejected", reloc.indexes_rejected},
        {"chunks_rejected", relocalizer_->chunks_rejected()},
        {"attempts", reloc.attempts},
        {"found", reloc.found},
        {"found_from_trajectory", reloc.found_from_trajectory},
        {"ambiguous", reloc.ambiguous},
        {"mean_ms", reloc.attempts > 0 ? reloc.total_ms / reloc.attempts : 0.0}}}};
  summary["position_update"] =
      position_update_ ? ToJson(position_update_->stats()) : nlohmann::json::object();
  summary["position_update"]["enabled"] = position_update_ != nullptr;
  summary["capture_to_pose_ms"] = capture_latency_.Summary();
  summary["odometry_extrapolation"] = {{"frames", extrapolated_frames_},
                                       {"max_ms", max_extrapolated_s_ * 1000.0},
                                       {"horizon_ms", extrapolation_s_ * 1000.0}};
  summary["input_dropped_frames"] = input_ ? input_->DroppedFrames() : 0;
  return io::WriteFileAtomically(config_.summary_path, summary.dump(2) + "\n");
}

Status TrackerAgent::Run(VehicleInput& input, const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(config_.health_period_s));
  if (config_.start_pose == "relocalize") WaitForPlaceIndex();
  input_ = &input;
  if (initial_) WarmUp(0.0, *initial_);
  auto next_health = Clock::now();
  while (!stop.load()) {
    io::NotifyServiceAlive();  // READY=1, then the systemd watchdog
    Result<std::optional<InputEvent>> event = input.Next();
    if (!event.ok()) {
      health_.RecordDroppedFrame(event.status().message());
      spdlog::warn("{}", event.status().message());
      continue;
    }
    if (!event->has_value()) break;
    InputEvent& e = **event;
    if (ros_) {
      if (std::optional<transport::RosPoseStamped> given = ros_->TakeInitialPose()) ApplyInitialPose(*given);
    }
    if (e.kind == InputEvent::Kind::kIdle) {
      // nothing arrived: housekeeping only
    } else if (e.kind == InputEvent::Kind::kOdometryRestart) {
      OnOdometryRestart();
    } else if (e.kind == InputEvent::Kind::kOdometry) {
      OnOdometry(e.t, e.odom);
    } else if (e.kind == InputEvent::Kind::kFrame || position_update_) {
      // A forward image is not rectified: its detector has its own camera model.
      const bool forward = e.kind == InputEvent::Kind::kForwardFrame;
      const cv::Mat image = forward || !rectifier_ ? e.frame : rectifier_->Rectify(e.frame);
      waiting_frames_.push_back({e.t, forward, image, {e.t, e.arrival_t, e.taken_t}});
      ProcessReadyFrames();
    }
    UpdateMapServerReachability();
    ApplyTileUpdates();
    if (IsLiveSource(config_.source)) DecodeArrivedTiles(kTilesDecodedPerTurn);
    WarmUpTracker();
    relocalizer_->Poll();
    PumpPatches();
    if (Clock::now() >= next_health) PublishHealth(), next_health = Clock::now() + period;
    if (metrics_->Due()) RefreshMetrics();
  }
  io::NotifyServiceStopping();
  DrainPatches(stop);
  PublishHealth();
  const Status summary = config_.summary_path.empty() ? Status::Ok() : WriteSummary();
  input_ = nullptr;
  FLEETLOC_RETURN_IF_ERROR(summary);
  spdlog::info("stopping after {} frames (cycle median {:.2f} ms)", health_.frames(), health_.CyclePercentile(50));
  return Status::Ok();
}

}  // namespace fleetloc::tracker_agent
