// RemapCommand validation, job queue and worker thread with RemapStatus reports.
#include "map_server/remap_service.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "transport/remap_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::map_server {

using transport::GetBounded;

std::vector<std::string> RemapService::CounterNames() {
  return {"remap_commands", "remap_jobs_done", "remap_jobs_failed", "rejected_remap_command",
          "patches_folded", "patches_refused", "patches_held",      "vehicles_quarantined"};
}

RemapService::RemapService(std::string server_id, RemapRunner runner,
                           const transport::Writer<fleetloc_RemapStatus>* status_writer,
                           ServerCounters* counters, Maintenance maintenance)
    : server_id_(std::move(server_id)),
      runner_(std::move(runner)),
      maintenance_(std::move(maintenance)),
      status_writer_(status_writer),
      counters_(counters),
      worker_([this] { Work(); }) {}

RemapService::~RemapService() {
  stopping_ = true;
  wake_.notify_all();
  worker_.join();
}

namespace {

// Why `c` cannot be run against `layout`, or "" if it can.
std::string Problem(const fleetloc_RemapCommand& c, const mosaic::MosaicLayout& layout) {
  if (c.wire_version != fleetloc_CURRENT_WIRE_VERSION) {
    return "unknown wire_version " + std::to_string(c.wire_version);
  }
  const std::string mosaic_id = GetBounded(c.mosaic_id);
  if (!mosaic_id.empty() && mosaic_id != layout.mosaic_id)
    return "unknown mosaic '" + mosaic_id + "'";
  const fleetloc_MapRegion& r = c.region;
  for (double v : {r.x_min, r.y_min, r.x_max, r.y_max}) {
    if (!std::isfinite(v)) return "region has a non-finite coordinate";
  }
  if (!(r.x_min < r.x_max && r.y_min < r.y_max)) return "region is empty or inverted";
  const double x0 = layout.geo.origin_x, y1 = layout.geo.origin_y;
  const double x1 = x0 + layout.width_px * layout.geo.resolution;
  const double y0 = y1 - layout.height_px * layout.geo.resolution;
  if (r.x_max <= x0 || r.x_min >= x1 || r.y_max <= y0 || r.y_min >= y1) {
    return "region lies outside the mosaic";
  }
  if (c.mode != fleetloc_REMAP_BLEND && c.mode != fleetloc_REMAP_REPLACE) return "unknown mode";
  return "";
}

}  // namespace

void RemapService::Receive(const fleetloc_RemapCommand& c, const mosaic::MosaicLayout& layout) {
  counters_->Add("remap_commands");
  if (const std::string problem = Problem(c, layout); !problem.empty()) {
    counters_->Reject("rejected_remap_command",
                      "RemapCommand " + std::to_string(c.command_id) + ": " + problem);
    Publish(c.command_id, fleetloc_REMAP_REJECTED, "", 0, problem);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    queue_.push_back({c.command_id, c.region.x_min, c.region.y_min, c.region.x_max, c.region.y_max,
                      c.mode == fleetloc_REMAP_REPLACE});
  }
  spdlog::info("remap {} queued by '{}'", c.command_id, GetBounded(c.requester));
  Publish(c.command_id, fleetloc_REMAP_QUEUED, "queued", 0, "");
  wake_.notify_one();
}

std::vector<RemapOutcome> RemapService::TakeFinished() {
  std::lock_guard lock(mutex_);
  return std::exchange(finished_, {});
}

bool RemapService::WaitForJob(RemapJob* job) {
  using Clock = std::chrono::steady_clock;
  const bool periodic = maintenance_.period_s > 0 && maintenance_.run;
  if (periodic && next_maintenance_ <= Clock::now()) {
    maintenance_.run();
    next_maintenance_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(maintenance_.period_s));
  }
  std::unique_lock lock(mutex_);
  const auto ready = [&] { return stopping_.load() || !queue_.empty(); };
  if (periodic) {
    if (!wake_.wait_until(lock, next_maintenance_, ready)) return false;
  } else {
    wake_.wait(lock, ready);
  }
  if (stopping_ || queue_.empty()) return false;
  *job = queue_.front();
  queue_.pop_front();
  return true;
}

void RemapService::Work() {
  while (!stopping_) {
    RemapJob job;
    if (!WaitForJob(&job)) continue;
    auto last_report = std::chrono::steady_clock::now() - std::chrono::seconds(1);
    const RemapProgressFn progress = [&](const std::string& phase, double fraction) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_report < std::chrono::milliseconds(200) && fraction < 1.0) return;
      last_report = now;
      Publish(job.command_id, fleetloc_REMAP_RUNNING, phase, fraction, "");
    };
    Publish(job.command_id, fleetloc_REMAP_RUNNING, "start", 0, "");
    Result<RemapOutcome> outcome = runner_(job, progress, stopping_);
    if (!outcome.ok()) {
      counters_->Reject("remap_jobs_failed", "remap " + std::to_string(job.command_id) + ": " +
                                                 outcome.status().message());
      Publish(job.command_id, fleetloc_REMAP_FAILED, "failed", 0, outcome.status().message());
      continue;
    }
    counters_->Add("remap_jobs_done");
    counters_->Add("patches_folded", static_cast<uint64_t>(outcome->patches_folded));
    counters_->Add("patches_refused", static_cast<uint64_t>(outcome->patches_rejected));
    counters_->Add("patches_held", static_cast<uint64_t>(outcome->patches_held));
    spdlog::info("remap {} done: version {}, {} tiles; {}", job.command_id, outcome->new_version,
                 outcome->changed_tiles.size(), outcome->summary);
    for (const std::string& vehicle : outcome->newly_quarantined) {
      counters_->Add("vehicles_quarantined");
      spdlog::warn(
          "vehicle '{}' quarantined: its patches keep failing admission; its patches are "
          "refused until `fleetctl mosaic vehicles MOSAIC --release {}`",
          vehicle, vehicle);
    }
    Publish(job.command_id, fleetloc_REMAP_DONE, "done", 1.0, outcome->summary, &*outcome);
    std::lock_guard lock(mutex_);
    finished_.push_back(std::move(outcome).value());
  }
}

void RemapService::Publish(uint64_t id, fleetloc_RemapState state, const std::string& phase,
                           double progress, const std::string& message,
                           const RemapOutcome* outcome) {
  transport::RemapProgress p;
  p.command_id = id;
  p.server_id = server_id_;
  p.state = state;
  p.phase = phase;
  p.progress = progress;
  p.message = message;
  if (outcome != nullptr) {
    p.new_version = outcome->new_version;
    p.tiles_changed = static_cast<uint32_t>(outcome->changed_tiles.size());
    p.patches_folded = static_cast<uint32_t>(outcome->patches_folded);
    p.patches_rejected = static_cast<uint32_t>(outcome->patches_rejected);
  }
  const fleetloc_RemapStatus status = transport::ToIdl(p, transport::NowStamp());
  if (Status sent = status_writer_->Write(status); !sent.ok()) spdlog::warn("{}", sent.message());
}

}  // namespace fleetloc::map_server
