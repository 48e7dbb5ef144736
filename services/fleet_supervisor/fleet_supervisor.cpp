// FleetSupervisor: wiring and the DDS loop.
#include "fleet_supervisor/fleet_supervisor.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "fleet_supervisor/supervisor_metrics.h"
#include "io/json_fields.h"
#include "runtime/child_process.h"
#include "runtime/service_notify.h"
#include "transport/service_health_messages.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::fleet_supervisor {

namespace {

constexpr double kFlushPeriodS = 1.0;   // history rows are written in one transaction per second
constexpr double kPrunePeriodS = 60.0;  // retention runs once a minute
constexpr double kAlertPeriodS = 0.1;
constexpr double kMapServerTimeoutS = 5.0;
constexpr dds_attach_t kFleetData = 1;
constexpr double kMaxStepGapS = 2.0;  // /readyz: the loop steps every 10 ms when healthy

// Moves a created object into *out; its Status otherwise.
template <typename T>
Status MoveTo(Result<std::unique_ptr<T>> created, std::unique_ptr<T>* out) {
  if (!created.ok()) return created.status();
  *out = std::move(created).value();
  return Status::Ok();
}

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double SteadyNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

FleetSupervisor::FleetSupervisor(const SupervisorConfig& config) : config_(config) {}

FleetSupervisor::~FleetSupervisor() {
  if (http_) http_->Stop();
}

Result<std::unique_ptr<FleetSupervisor>> FleetSupervisor::Create(const SupervisorConfig& config) {
  FLEETLOC_RETURN_IF_ERROR(Validate(config));
  std::unique_ptr<FleetSupervisor> supervisor(new FleetSupervisor(config));
  FLEETLOC_RETURN_IF_ERROR(supervisor->Open());
  return supervisor;
}

std::string FleetSupervisor::ResolveWebDir() const {
  if (!config_.web_dir.empty()) return config_.web_dir;
  namespace fs = std::filesystem;
  const fs::path exe = runtime::ExecutableDir();
  for (const fs::path& candidate :
       {exe / "../share/fleetloc/fleet_supervisor/web", exe / "fleet_supervisor_web",
        fs::path(FLEETLOC_SUPERVISOR_WEB_DIR)}) {
    std::error_code ec;
    if (fs::is_regular_file(candidate / "index.html", ec))
      return candidate.lexically_normal().string();
  }
  return FLEETLOC_SUPERVISOR_WEB_DIR;
}

Status FleetSupervisor::Open() {
  Result<std::string> token = ResolveMaintainerToken(config_);
  if (!token.ok()) return token.status();
  FLEETLOC_RETURN_IF_ERROR(MoveTo(HistoryStore::Open(config_.history_db), &history_));
  fleet_ = std::make_unique<SharedFleet>(config_.alerts, config_.trail, config_.history_period_s);
  FLEETLOC_RETURN_IF_ERROR(Restore());
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Participant::Create(config_.domain_id, {"", config_.dds_config_path}),
               &participant_));
  const transport::Participant& p = *participant_;
  FLEETLOC_RETURN_IF_ERROR(MoveTo(fleet_link::FleetListener::Create(p), &listener_));
  auto client = transport::TileClient::Create(p, config_.supervisor_id);
  if (!client.ok()) return client.status();
  tiles_ = std::make_unique<OverviewTiles>(
      std::move(client).value(), static_cast<size_t>(config_.tile_cache_mb) << 20,
      std::chrono::milliseconds(static_cast<int>(config_.tile_timeout_s * 1000)),
      config_.min_tile_level);
  FLEETLOC_RETURN_IF_ERROR(MoveTo(transport::RemapClient::Create(p), &remap_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(
      transport::Topic<fleetloc_ServiceHealth>::Create(p, transport::topics::kServiceHealth),
      &health_topic_));
  const double period = config_.health_period_s;
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Writer<fleetloc_ServiceHealth>::Create(
                   p.get(), *health_topic_, transport::PeriodicStateQos(3 * period, 5 * period)),
               &health_writer_));
  FLEETLOC_RETURN_IF_ERROR(AssignTo(transport::WaitSet::Create(p), &waitset_));
  FLEETLOC_RETURN_IF_ERROR(waitset_->AttachReader(listener_->pose_reader(), kFleetData));
  FLEETLOC_RETURN_IF_ERROR(waitset_->AttachReader(listener_->health_reader(), kFleetData));
  FLEETLOC_RETURN_IF_ERROR(waitset_->AttachReader(tiles_->tile_reader(), kFleetData));
  ApiContext context;
  context.config = &config_;
  context.maintainer_token = *token;
  context.fleet = fleet_.get();
  context.history = history_.get();
  context.tiles = tiles_.get();
  context.stream = &stream_;
  context.start_remap = [this](const transport::RemapRequest& r) { return remap_->Send(r); };
  context.map_server_listening = [this] { return remap_->ServerMatched(); };
  context.readiness = [this] { return Readiness(); };
  http_ = std::make_unique<HttpApi>(std::move(context));
  FLEETLOC_RETURN_IF_ERROR(http_->Start(ResolveWebDir()));
  if (!config_.port_file.empty()) {
    std::ofstream(config_.port_file) << http_->port() << "\n";
  }
  metrics_ = std::make_unique<metrics::ServiceMetrics>(config_.metrics, "fleet_supervisor");
  if (config_.vda5050.enabled)
    FLEETLOC_RETURN_IF_ERROR(
        MoveTo(Vda5050Publisher::Start(config_.vda5050, config_.supervisor_id), &vda_));
  return Status::Ok();
}

void FleetSupervisor::RefreshMetrics(double now) {
  metrics::FamilyBuilder b(kSupervisorMetricPrefix, {{"service_id", config_.supervisor_id}});
  fleet_->AddMetrics(&b);
  AddSupervisorFamilies(AllCounters(), fleet_->MapServerAlive(now, kMapServerTimeoutS), &b);
  if (vda_)
    b.Gauge("vda5050_connected", "1 while connected to the MQTT broker", vda_->connected() ? 1 : 0);
  metrics_->Publish(b.Take());
}

Status FleetSupervisor::Restore() {
  Result<std::vector<fleet::VehicleState>> vehicles = history_->LatestVehicles();
  if (!vehicles.ok()) return vehicles.status();
  Result<std::vector<fleet::Alert>> open = history_->Alerts({"", true, 100000});
  if (!open.ok()) return open.status();
  fleet_->Restore(*vehicles, *open);
  spdlog::info("history {}: {} vehicles, {} open alerts restored", config_.history_db,
               vehicles->size(), open->size());
  return Status::Ok();
}

void FleetSupervisor::StoreAlerts(const std::vector<fleet::Alert>& changes) {
  for (const fleet::Alert& a : changes) {
    spdlog::log(a.cleared_t ? spdlog::level::info : spdlog::level::warn, "alert {} {} {}: {}",
                a.cleared_t ? "cleared" : "raised", a.vehicle_id, fleet::AlertKindName(a.kind),
                a.message);
    if (a.cleared_t) {
      if (a.id > 0 && !history_->CloseAlert(a.id, *a.cleared_t).ok())
        ++fleet_->counters().history_errors;
      continue;
    }
    Result<long long> id = history_->InsertAlert(a);
    if (!id.ok()) {
      ++fleet_->counters().history_errors;
      continue;
    }
    fleet_->SetAlertId(a, *id);
  }
}

// Ready: the main loop takes DDS data (it stepped within kMaxStepGapS), the newest history flush
// succeeded, and /metrics serves when configured.
std::vector<ReadinessCheck> FleetSupervisor::Readiness() const {
  const double gap = SteadyNow() - last_step_.load();
  std::vector<ReadinessCheck> checks = {
      {"dds", gap < kMaxStepGapS,
       gap < kMaxStepGapS ? "" : "the DDS loop has not run for " + std::to_string(gap) + " s"},
      {"history", history_written_.load(),
       history_written_.load() ? "" : config_.history_db + ": the newest write failed"},
  };
  if (metrics_) {
    const std::string error = metrics_->error();
    checks.push_back({"metrics", error.empty(), error});
  }
  return checks;
}

void FleetSupervisor::FlushHistory(double now) {
  if (Status written = history_->Append(pending_poses_, pending_health_); !written.ok()) {
    history_written_ = false;
    ++fleet_->counters().history_errors;
    spdlog::error("{}", written.message());
  } else {
    history_written_ = true;
    fleet_->counters().history_rows += pending_poses_.size() + pending_health_.size();
  }
  pending_poses_.clear();
  pending_health_.clear();
  fleet_->counters().history_queue = 0;
  if (now >= next_prune_) {
    next_prune_ = now + kPrunePeriodS;
    Result<long long> pruned = history_->Prune(now - config_.retention_s);
    if (!pruned.ok())
      spdlog::error("{}", pruned.status().message());
    else if (*pruned > 0)
      spdlog::info("retention: {} history rows deleted", *pruned);
  }
}

void FleetSupervisor::Step(double now) {
  last_step_ = SteadyNow();
  fleet_link::Received received;
  if (Status taken = listener_->Take(&received); !taken.ok()) spdlog::error("{}", taken.message());
  fleet_->Apply(received, now, &pending_poses_, &pending_health_);
  fleet_->counters().history_queue = pending_poses_.size() + pending_health_.size();
  tiles_->Pump();
  if (Result<std::vector<transport::RemapProgress>> jobs = remap_->TakeStatuses();
      jobs.ok() && !jobs->empty()) {
    fleet_->OnRemapStatus(*jobs);
  }
  if (now >= next_alerts_) {
    next_alerts_ = now + kAlertPeriodS;
    StoreAlerts(fleet_->Evaluate(now));
    fleet_->counters().deadline_misses = listener_->DeadlineMisses();
  }
  if (now >= next_flush_) {
    next_flush_ = now + kFlushPeriodS;
    FlushHistory(now);
  }
  if (now >= next_snapshot_) {
    next_snapshot_ = now + config_.stream_period_s;
    nlohmann::json snapshot = fleet_->Snapshot(now);
    const std::optional<mosaic::MosaicLayout> layout = tiles_->Layout();
    snapshot["mosaic"] =
        layout ? nlohmann::json{{"mosaic_id", layout->mosaic_id}, {"version", layout->version}}
               : nlohmann::json(nullptr);
    snapshot["map_server_alive"] = fleet_->MapServerAlive(now, kMapServerTimeoutS);
    stream_.Publish(io::DumpJson(snapshot));
    ++fleet_->counters().stream_snapshots;
  }
  if (metrics_->Due()) RefreshMetrics(now);
  if (vda_ && vda_->Due(now)) {
    const std::optional<mosaic::MosaicLayout> layout = tiles_->Layout();
    vda_->Publish(fleet_->LatestPoses(), layout ? layout->mosaic_id : "unknown", now);
  }
  if (now >= next_health_) {
    next_health_ = now + config_.health_period_s;
    if (Status sent = PublishHealth(); !sent.ok()) spdlog::warn("{}", sent.message());
  }
}

Status FleetSupervisor::PublishHealth() {
  transport::ServiceHealthReport report{config_.supervisor_id, "fleet_supervisor", std::nullopt,
                                        AllCounters()};
  if (fleet_->counters().history_errors > 0) {
    report.issue = {"history_errors", fleetloc_HEALTH_ERROR,
                    "the SQLite history could not be written"};
  } else if (vda_ && !vda_->connected()) {
    report.issue = {"vda5050_broker_unreachable", fleetloc_HEALTH_WARN, vda_->problem()};
  } else if (!metrics_->error().empty()) {
    report.issue = {"metrics_unavailable", fleetloc_HEALTH_WARN, metrics_->error()};
  }
  return transport::WriteServiceHealth(*health_writer_, report);
}

std::vector<std::pair<std::string, uint64_t>> FleetSupervisor::AllCounters() const {
  std::vector<std::pair<std::string, uint64_t>> counters = fleet_->counters().Snapshot();
  if (vda_) {
    for (auto& c : vda_->Counters()) counters.push_back(std::move(c));
  }
  return counters;
}

Status FleetSupervisor::Run(const std::atomic<bool>& stop) {
  while (!stop.load()) {
    runtime::NotifyServiceAlive();  // READY=1, then the systemd watchdog
    Result<std::vector<dds_attach_t>> woke = waitset_->Wait(0.01);
    if (!woke.ok()) return woke.status();
    Step(Now());
  }
  runtime::NotifyServiceStopping();
  http_->Stop();
  vda_.reset();  // OFFLINE, retained
  fleet_->NewestUnstored(&pending_poses_);
  FlushHistory(Now());
  spdlog::info("stopping: {} poses and {} health reports received, {} history rows written",
               fleet_->counters().poses_received.load(), fleet_->counters().health_received.load(),
               fleet_->counters().history_rows.load());
  return Status::Ok();
}

}  // namespace fleetloc::fleet_supervisor
