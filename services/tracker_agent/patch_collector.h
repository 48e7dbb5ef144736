// The tracker agent's patch collection: tracked frames that show floor the mosaic does not
// (changed or unmapped) are queued in the persistent outbox and sent to the map servers owning
// the mosaic until every replica acknowledged them (or one rejected them).
#pragma once

#include <atomic>
#include <memory>

#include "mosaic/mosaic_view.h"
#include "tracker_agent/agent_config.h"
#include "tracker_agent/health_counters.h"
#include "tracker_agent/localization_ports.h"
#include "tracker_agent/map_server_directory.h"
#include "tracker_agent/patch_outbox.h"
#include "transport/patch_client.h"

namespace fleetloc::tracker_agent {

class PatchCollector : public TrackedFrameObserver {
 public:
  // Opens the outbox (config.outbox_path, else fleetloc-outbox-<vehicle>.db) and the patch topics.
  // `layout` (kept current by the DDS link), `view`, `map_servers` and `health` must outlive it.
  static Result<std::unique_ptr<PatchCollector>> Create(
      const transport::Participant& participant, const AgentConfig& config,
      const geometry::CameraModel& camera, const mosaic::MosaicLayout* layout,
      mosaic::RasterSource* view, const MapServerDirectory* map_servers, HealthCounters* health);

  // Queues the frame as a patch when it tracked and shows floor the mosaic does not (rate-limited).
  void FrameTracked(double t, const cv::Mat& frame, const tracking::FrameResult& result) override;
  // Takes acknowledgements and (re)sends what is due, while `map_server_reachable`.
  void Pump(bool map_server_reachable);
  // At the end of the input: keeps pumping until the outbox is empty, drain_s passed or `stop`.
  void Drain(const std::atomic<bool>& stop, bool map_server_reachable);
  // Patches waiting, and those the full outbox dropped (0 when the outbox cannot tell).
  long long waiting();
  long long dropped();

 private:
  PatchCollector(const AgentConfig& config, const geometry::CameraModel& camera,
                 const mosaic::MosaicLayout* layout, mosaic::RasterSource* view,
                 const MapServerDirectory* map_servers, HealthCounters* health)
      : config_(config),
        camera_(camera),
        layout_(*layout),
        view_(view),
        map_servers_(*map_servers),
        health_(*health) {}
  // One acknowledgement (DecideAck): counts it for its replica, or drops a rejected patch.
  void TakeAck(const transport::ReceivedAck& ack);

  AgentConfig config_;
  geometry::CameraModel camera_;
  const mosaic::MosaicLayout& layout_;
  mosaic::RasterSource* view_;
  const MapServerDirectory& map_servers_;
  HealthCounters& health_;
  std::unique_ptr<transport::PatchClient> patches_;
  std::unique_ptr<PatchOutbox> outbox_;
  double last_patch_t_ = -1e300;
};

}  // namespace fleetloc::tracker_agent
