// TrackerAgent's patch collection: frames that show floor the mosaic does not (changed or
// unmapped) are queued in the persistent outbox and sent to the map server until acknowledged.
#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include "mapping/change_detection.h"
#include "mosaic/tile_codec.h"
#include "tracker_agent/patch_acks.h"
#include "tracker_agent/tracker_agent.h"
#include "tracking/predicted_view.h"

namespace fleetloc::tracker_agent {

void TrackerAgent::MaybeCollectPatch(double t, const cv::Mat& frame,
                                     const tracking::FrameResult& result) {
  if (result.state != tracking::LockState::kTracking || t - last_patch_t_ < config_.patch_min_interval_s) return;
  const geometry::Pose2 camera = result.base_in_map.pose * camera_.model.mount;
  const cv::Mat view = tracking::RenderPredictedView(
      view_.get(), {0, 0, frame.cols, frame.rows},
      tracking::FrameMosaicWarp::For(camera, camera_.model, layout_.geo), 0);
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
  const geometry::PoseWithCovariance cam = geometry::ComposeFixed(result.base_in_map, camera_.model.mount);
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(patch.covariance) = cam.covariance;
  patch.quality = static_cast<float>(std::min(1.0, result.inliers / 20.0));
  patch.resolution_m = camera_.model.resolution_m;
  patch.png = std::move(png).value();
  Result<uint64_t> added = outbox_->Add(&patch);
  if (!added.ok()) return health_.RecordError(added.status().message());
  spdlog::info("patch {} queued: of {} blocks, {} differ from the mosaic and {} are not mapped",
               *added, change.blocks, change.changed, change.unmapped);
}

void TrackerAgent::TakeAck(const transport::ReceivedAck& ack) {
  const AckDecision decision = DecideAck(ack, map_servers_->servers());
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
          outbox_->Acknowledge(ack.sequence, decision.server, map_servers_->servers());
      if (!done.ok()) health_.RecordError(done.status().message());
      return;
    }
  }
}

void TrackerAgent::PumpPatches() {
  Result<std::vector<transport::ReceivedAck>> acks = patches_->TakeAcks();
  if (acks.ok()) {
    for (const transport::ReceivedAck& ack : *acks) TakeAck(ack);
  }
  // Keep them for when the server is back (a dead server stays matched until its lease ends),
  // and until every replica is known: sent while a server that was down at our start is not yet
  // announced, a patch would leave the outbox with that replica never having it.
  if (!patches_->ServerMatched() || !map_server_reachable_ || map_servers_->UncoveredTiles() > 0)
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

void TrackerAgent::DrainPatches(const std::atomic<bool>& stop) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(config_.drain_s);
  Result<long long> left = outbox_->Size();
  while (!stop.load() && left.ok() && *left > 0 && std::chrono::steady_clock::now() < end) {
    PumpPatches();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    left = outbox_->Size();
  }
  if (left.ok() && *left > 0) spdlog::warn("{} patches stay in the outbox for the next start", *left);
}

}  // namespace fleetloc::tracker_agent
