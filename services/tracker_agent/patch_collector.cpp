// PatchCollector: frames that show floor the mosaic does not are queued in the persistent outbox
// and sent to the map servers until acknowledged.
#include "tracker_agent/patch_collector.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include "mapping/change_detection.h"
#include "mosaic/tile_codec.h"
#include "tracker_agent/patch_acks.h"
#include "tracking/predicted_view.h"

namespace fleetloc::tracker_agent {

Result<std::unique_ptr<PatchCollector>> PatchCollector::Create(
    const transport::Participant& participant, const AgentConfig& config,
    const geometry::CameraModel& camera, const mosaic::MosaicLayout* layout,
    mosaic::RasterSource* view, const MapServerDirectory* map_servers, HealthCounters* health) {
  std::unique_ptr<PatchCollector> collector(
      new PatchCollector(config, camera, layout, view, map_servers, health));
  auto patches = transport::PatchClient::Create(participant, config.vehicle_id);
  if (!patches.ok()) return patches.status();
  collector->patches_ = std::move(patches).value();
  const std::string outbox_path = config.outbox_path.empty()
                                      ? "fleetloc-outbox-" + config.vehicle_id + ".db"
                                      : config.outbox_path;
  auto outbox = PatchOutbox::Open(
      outbox_path, {config.outbox_max_patches, static_cast<long long>(config.outbox_max_mb) << 20});
  if (!outbox.ok()) return outbox.status();
  collector->outbox_ = std::move(outbox).value();
  return collector;
}

void PatchCollector::FrameTracked(double t, const cv::Mat& frame,
                                  const tracking::FrameResult& result) {
  if (result.state != tracking::LockState::kTracking ||
      t - last_patch_t_ < config_.patch_min_interval_s)
    return;
  const geometry::Pose2 camera = result.base_in_map.pose * camera_.mount;
  const cv::Mat view = tracking::RenderPredictedView(
      view_, {0, 0, frame.cols, frame.rows},
      tracking::FrameMosaicWarp::For(camera, camera_, layout_.geo), 0);
  const mapping::ChangeReport change = mapping::CompareWithMosaic(frame, view);
  if (change.changed_fraction() < config_.patch_min_changed) return;
  last_patch_t_ = t;
  Result<std::vector<std::uint8_t>> png = mosaic::EncodeTile(frame);
  if (!png.ok()) return health_.RecordError(png.status().message());
  transport::PatchToSend patch;
  patch.stamp_s = t;
  patch.mosaic_id = layout_.mosaic_id;
  patch.mosaic_version = layout_.version;
  patch.pose = camera;  // camera_ground of the image centre (principal point)
  // The camera pose's covariance: the base's, carried through the rigid mount (first order).
  const geometry::PoseWithCovariance cam =
      geometry::ComposeFixed(result.base_in_map, camera_.mount);
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(patch.covariance) = cam.covariance;
  patch.quality = static_cast<float>(std::min(1.0, result.inliers / 20.0));
  patch.resolution_m = camera_.resolution_m;
  patch.png = std::move(png).value();
  Result<uint64_t> added = outbox_->Add(&patch);
  if (!added.ok()) return health_.RecordError(added.status().message());
  spdlog::info("patch {} queued: of {} blocks, {} differ from the mosaic and {} are not mapped",
               *added, change.blocks, change.changed, change.unmapped);
}

void PatchCollector::TakeAck(const transport::ReceivedAck& ack) {
  const AckDecision decision = DecideAck(ack, map_servers_.servers());
  switch (decision.action) {
    case AckAction::kIgnore:
      spdlog::debug("patch {}: answer from '{}' ignored (not a replica of mosaic {})", ack.sequence,
                    ack.server_id, layout_.mosaic_id);
      return;
    case AckAction::kDrop:
      spdlog::warn("patch {} rejected by '{}': {}", ack.sequence, decision.server, ack.reason);
      if (Status removed = outbox_->Remove(ack.sequence); !removed.ok())
        health_.RecordError(removed.message());
      return;
    case AckAction::kCount: {
      Result<bool> done =
          outbox_->Acknowledge(ack.sequence, decision.server, map_servers_.servers());
      if (!done.ok()) health_.RecordError(done.status().message());
      return;
    }
  }
}

void PatchCollector::Pump(bool map_server_reachable) {
  Result<std::vector<transport::ReceivedAck>> acks = patches_->TakeAcks();
  if (acks.ok()) {
    for (const transport::ReceivedAck& ack : *acks) TakeAck(ack);
  }
  // Keep them for when the server is back (a dead server stays matched until its lease ends),
  // and until every replica is known: sent while a server that was down at our start is not yet
  // announced, a patch would leave the outbox with that replica never having it.
  if (!patches_->ServerMatched() || !map_server_reachable || map_servers_.UncoveredTiles() > 0)
    return;
  // Monotonic time with the boot it belongs to: after a reboot every unacknowledged patch is due.
  const OutboxTime now = OutboxNow();
  Result<std::vector<transport::PatchToSend>> due = outbox_->Due(now, config_.patch_retry_s, 2);
  if (!due.ok()) return health_.RecordError(due.status().message());
  for (const transport::PatchToSend& patch : *due) {
    if (Status sent = patches_->Send(patch); !sent.ok()) return health_.RecordError(sent.message());
    (void)outbox_->MarkSent(patch.sequence, now);
  }
}

void PatchCollector::Drain(const std::atomic<bool>& stop, bool map_server_reachable) {
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(config_.drain_s);
  Result<long long> left = outbox_->Size();
  while (!stop.load() && left.ok() && *left > 0 && std::chrono::steady_clock::now() < end) {
    Pump(map_server_reachable);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    left = outbox_->Size();
  }
  if (left.ok() && *left > 0)
    spdlog::warn("{} patches stay in the outbox for the next start", *left);
}

long long PatchCollector::waiting() {
  const Result<long long> size = outbox_->Size();
  return size.ok() ? *size : 0;
}

long long PatchCollector::dropped() {
  const Result<long long> dropped = outbox_->Dropped();
  return dropped.ok() ? *dropped : 0;
}

}  // namespace fleetloc::tracker_agent
