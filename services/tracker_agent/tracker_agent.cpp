// TrackerAgent: wires the localization core to the DDS link and the patch collector, and pumps
// them from the vehicle's input; health, metrics and the summary gather what the three count.
#include "tracker_agent/tracker_agent.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "io/file_util.h"
#include "runtime/service_notify.h"
#include "tracker_agent/agent_metrics.h"

namespace fleetloc::tracker_agent {

LocalizationOptions LocalizationOptionsFor(const AgentConfig& config) {
  LocalizationOptions o;
  o.live = IsLiveSource(config.source);
  o.odometry_extrapolation_s = o.live ? config.live.odometry_extrapolation_s : 0.0;
  o.odometry_stale_s = config.live.odometry_stale_s;
  o.relocalize_on_lost = config.relocalize_on_lost;
  o.relocalize_after_coasting_frames = config.relocalize_after_coasting_frames;
  o.relocalize_interval_s = config.relocalize_interval_s;
  o.prefetch_margin_px = config.prefetch_margin_px;
  o.prefetch_ahead_s = config.prefetch_ahead_s;
  o.initial_pose_source = config.ros.initialpose_topic;
  return o;
}

Result<std::unique_ptr<TrackerAgent>> TrackerAgent::Create(
    const AgentConfig& config, const run_io::CameraFile& camera,
    const std::optional<geometry::PoseWithCovariance>& initial,
    const tracking::TrackerOptions& options, std::unique_ptr<AgentPositionUpdate> position_update) {
  FLEETLOC_RETURN_IF_ERROR(Validate(config));
  std::unique_ptr<TrackerAgent> agent(new TrackerAgent(config));
  auto link = DdsLink::Create(config, camera.model, &agent->health_);
  if (!link.ok()) return link.status();
  agent->link_ = std::move(link).value();
  DdsLink& dds = *agent->link_;
  auto patches = PatchCollector::Create(dds.participant(), config, camera.model, &dds.layout(),
                                        dds.view(), &dds.map_servers(), &agent->health_);
  if (!patches.ok()) return patches.status();
  agent->patches_ = std::move(patches).value();
  const LocalizationPorts ports{&dds, &dds.relocalizer(), &dds, agent->patches_.get(),
                                &agent->health_};
  agent->core_ = std::make_unique<LocalizationCore>(LocalizationOptionsFor(config), options, camera,
                                                    dds.layout(), dds.view(), initial, ports,
                                                    std::move(position_update));
  FLEETLOC_RETURN_IF_ERROR(dds.OpenRosBridge());
  agent->metrics_ = std::make_unique<metrics::ServiceMetrics>(config.metrics, "tracker_agent");
  if (!agent->metrics_->error().empty()) agent->health_.RecordError(agent->metrics_->error());
  return agent;
}

void TrackerAgent::HandleEvent(const InputEvent& e) {
  switch (e.kind) {
    case InputEvent::Kind::kIdle:  // nothing arrived: housekeeping only
      return;
    case InputEvent::Kind::kOdometryRestart:
      return core_->OnOdometryRestart();
    case InputEvent::Kind::kOdometry:
      return core_->OnOdometry(e.t, e.odom);
    case InputEvent::Kind::kFrame:
      return core_->AddDownwardFrame(e.t, e.frame, {e.t, e.arrival_t, e.taken_t});
    case InputEvent::Kind::kForwardFrame:
      return core_->AddForwardImage(e.t, e.frame);
  }
}

void TrackerAgent::PumpBetweenEvents() {
  link_->UpdateMapServerReachability();
  link_->ApplyTileUpdates(
      [this](const std::vector<mosaic::TileKey>& changed) { core_->DropTiles(changed); });
  core_->BetweenEvents();
  link_->relocalizer().Poll();
  patches_->Pump(link_->map_server_reachable());
  if (std::chrono::steady_clock::now() >= next_health_) {
    PublishHealth();
    next_health_ = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                       std::chrono::duration<double>(config_.health_period_s));
  }
  if (metrics_->Due()) RefreshMetrics();
}

void TrackerAgent::PublishHealth() {
  AgentHealth::Inputs in;
  in.vehicle_id = config_.vehicle_id;
  in.host_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  in.patch_outbox = static_cast<size_t>(patches_->waiting());
  in.position_update = core_->position_update() ? &core_->position_update()->stats() : nullptr;
  in.patch_outbox_dropped = patches_->dropped();
  if (input_ != nullptr) {
    in.input_issues = input_->Issues();
    in.input_dropped = input_->DroppedFrames();
  }
  link_->PublishHealth(std::move(in));
}

void TrackerAgent::RefreshMetrics() {
  AgentMetricsInput in;
  in.lock_state = core_->lock_state();
  in.frames = health_.frames();
  in.cycle_seconds = core_->cycle_seconds().Snapshot();
  in.tile_round_trip_seconds = link_->tile_round_trip().Snapshot();
  in.cache = link_->tile_cache().stats();
  in.loader = link_->loader().stats();
  in.tiles_pending = link_->loader().pending();
  in.outbox_patches = patches_->waiting();
  in.outbox_dropped = patches_->dropped();
  in.map_server_reachable = link_->map_server_reachable();
  in.relocalization_attempts = link_->relocalizer().stats().attempts;
  in.relocalization_found = link_->relocalizer().stats().found;
  metrics::FamilyBuilder b(kAgentMetricPrefix, {{"vehicle_id", config_.vehicle_id}});
  AddAgentFamilies(in, &b);
  metrics_->Publish(b.Take());
}

Status TrackerAgent::WriteSummary() {
  const AgentRelocalizer& relocalizer = link_->relocalizer();
  const RelocalizationStats& reloc = relocalizer.stats();
  const transport::DdsTileLoaderStats& tiles = link_->loader().stats();
  nlohmann::json summary{
      {"vehicle_id", config_.vehicle_id},
      {"frames", health_.frames()},
      {"cycle_ms",
       {{"median", health_.CyclePercentile(50, 10000)},
        {"p95", health_.CyclePercentile(95, 10000)},
        {"p99", health_.CyclePercentile(99, 10000)}}},
      {"tiles",
       {{"requested", tiles.requested},
        {"received", tiles.received},
        {"waited", tiles.waited},
        {"timeouts", tiles.timeouts},
        {"unserved", tiles.unserved},
        {"errors", tiles.errors},
        {"invalidated", tiles.invalidated},
        {"refreshed", tiles.refreshed},
        {"stale", tiles.stale},
        {"reasked", tiles.reasked}}},
      {"relocalization",
       {{"index_version", relocalizer.index_version()},
        {"indexes_loaded", reloc.indexes_loaded},
        {"indexes_rejected", reloc.indexes_rejected},
        {"chunks_rejected", relocalizer.chunks_rejected()},
        {"attempts", reloc.attempts},
        {"found", reloc.found},
        {"found_from_trajectory", reloc.found_from_trajectory},
        {"ambiguous", reloc.ambiguous},
        {"mean_ms", reloc.attempts > 0 ? reloc.total_ms / reloc.attempts : 0.0}}}};
  const AgentPositionUpdate* position_update = core_->position_update();
  summary["position_update"] =
      position_update ? ToJson(position_update->stats()) : nlohmann::json::object();
  summary["position_update"]["enabled"] = position_update != nullptr;
  summary["capture_to_pose_ms"] = link_->capture_latency().Summary();
  const ExtrapolationStats extrapolation = core_->extrapolation();
  summary["odometry_extrapolation"] = {{"frames", extrapolation.frames},
                                       {"max_ms", extrapolation.max_s * 1000.0},
                                       {"horizon_ms", extrapolation.horizon_s * 1000.0}};
  summary["input_dropped_frames"] = input_ ? input_->DroppedFrames() : 0;
  return io::WriteFileAtomically(config_.summary_path, summary.dump(2) + "\n");
}

Status TrackerAgent::Run(VehicleInput& input, const std::atomic<bool>& stop) {
  if (config_.start_pose == "relocalize") link_->WaitForPlaceIndex();
  input_ = &input;
  core_->WarmUpAtStart();
  next_health_ = std::chrono::steady_clock::now();
  while (!stop.load()) {
    runtime::NotifyServiceAlive();  // READY=1, then the systemd watchdog
    Result<std::optional<InputEvent>> event = input.Next();
    if (!event.ok()) {
      health_.RecordDroppedFrame(event.status().message());
      spdlog::warn("{}", event.status().message());
      continue;
    }
    if (!event->has_value()) break;
    if (std::optional<transport::RosPoseStamped> given = link_->TakeInitialPose()) {
      core_->ApplyInitialPose(given->t, given->pose);
    }
    HandleEvent(**event);
    PumpBetweenEvents();
  }
  runtime::NotifyServiceStopping();
  patches_->Drain(stop, link_->map_server_reachable());
  PublishHealth();
  const Status summary = config_.summary_path.empty() ? Status::Ok() : WriteSummary();
  input_ = nullptr;
  FLEETLOC_RETURN_IF_ERROR(summary);
  spdlog::info("stopping after {} frames (cycle median {:.2f} ms)", health_.frames(),
               health_.CyclePercentile(50));
  return Status::Ok();
}

}  // namespace fleetloc::tracker_agent
