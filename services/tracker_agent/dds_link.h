// The tracker agent's link to the fleet over DDS: it joins the domain, learns the mosaic from a
// map server's MosaicInfo, loads its tiles on demand through a byte-bounded cache (dropped when a
// TileUpdate announces a new version), keeps the directory of the map servers owning it, receives
// the place index, and publishes VehiclePose, VehicleHealth and, on live vehicles, the ROS 2
// poses, map -> odom and diagnostics. The localization core reads tiles and publishes through it.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "metrics/histogram.h"
#include "mosaic/mosaic_view.h"
#include "tracker_agent/agent_config.h"
#include "tracker_agent/agent_health.h"
#include "tracker_agent/agent_relocalizer.h"
#include "tracker_agent/capture_latency.h"
#include "tracker_agent/localization_ports.h"
#include "tracker_agent/map_server_directory.h"
#include "tracker_agent/ros_bridge.h"
#include "transport/dds_tile_loader.h"
#include "transport/pose_messages.h"
#include "transport/tile_client.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::tracker_agent {

class DdsLink : public TileSupply, public PosePublisher {
 public:
  // Joins config.domain_id, waits (up to mosaic_wait_s) for a map server's MosaicInfo and for
  // servers covering the whole mosaic, checks `camera`'s resolution against it and opens the
  // tiles and the place index channel. Errors it meets later go to `health`, which must outlive
  // the link.
  static Result<std::unique_ptr<DdsLink>> Create(const AgentConfig& config,
                                                 const geometry::CameraModel& camera,
                                                 AgentHealth* health);

  // The ROS 2 bridge (config.ros.enabled), opened last, once the agent is otherwise ready: the
  // vehicle's stack starts sending odometry and start poses when it sees the bridge's readers.
  Status OpenRosBridge();

  const transport::Participant& participant() const { return *participant_; }
  // The mosaic as announced, its version raised by each TileUpdate taken.
  const mosaic::MosaicLayout& layout() const { return layout_; }
  mosaic::MosaicView* view() { return view_.get(); }
  AgentRelocalizer& relocalizer() { return *relocalizer_; }
  const AgentRelocalizer& relocalizer() const { return *relocalizer_; }
  const MapServerDirectory& map_servers() const { return *map_servers_; }
  // Every map server owning part of the mosaic is reachable (as of the last poll).
  bool map_server_reachable() const { return map_server_reachable_; }
  const transport::DdsTileLoader& loader() const { return *loader_; }
  const mosaic::TileCache& tile_cache() const { return *tile_cache_; }
  const metrics::Histogram& tile_round_trip() const { return tile_round_trip_; }
  const CaptureLatency& capture_latency() const { return capture_latency_; }

  Status Prefetch(const std::vector<mosaic::TileKey>& keys) override;
  Result<size_t> DecodeArrived(size_t max_tiles) override;
  bool Settled() const override;
  bool Cached(const mosaic::TileKey& key) const override;

  void PublishPose(const PoseToPublish& pose) override;
  void PublishMapToOdom(double t, const geometry::Pose2& base_in_map,
                        const geometry::Pose2& base_in_odom) override;
  bool WantsMapToOdom() const override { return ros_ != nullptr; }

  // The newest start pose the vehicle's ROS 2 stack gave since the last call (nullopt: none, or
  // no ROS 2 bridge).
  std::optional<transport::RosPoseStamped> TakeInitialPose();
  // Takes the TileUpdates of newer versions of our mosaic: their tiles leave the cache, then
  // `drop_from_tracker` is told of them, then the loader forgets them.
  void ApplyTileUpdates(
      const std::function<void(const std::vector<mosaic::TileKey>&)>& drop_from_tracker);
  // A map server is reachable when it reads our tile requests (DDS match) and was heard from
  // (ServiceHealth) within map_server_timeout_s; the tile loader stops waiting for the tiles of
  // one that is not.
  void UpdateMapServerReachability();
  // A vehicle that starts without a pose can do nothing before the place index is loaded: waits
  // for it (at most mosaic_wait_s) so that its first frames are relocalized, not dropped.
  void WaitForPlaceIndex();
  // Fills the tile, map server and place index fields of `in`, and publishes the VehicleHealth
  // (and the ROS 2 diagnostics).
  void PublishHealth(AgentHealth::Inputs in);

 private:
  DdsLink(const AgentConfig& config, AgentHealth* health) : config_(config), health_(*health) {}
  Status OpenStreams();
  // Waits until a map server announces the mosaic and reads our tile requests, or `deadline`.
  Status AwaitMosaic(std::chrono::steady_clock::time_point deadline);
  Status OpenTiles(std::chrono::steady_clock::time_point deadline);
  // Until every tile of the mosaic has a map server announcing it, or `deadline`.
  void WaitForTileCoverage(std::chrono::steady_clock::time_point deadline);
  Status OpenRelocalizer(const geometry::CameraModel& camera);

  AgentConfig config_;
  AgentHealth& health_;
  std::unique_ptr<transport::Participant> participant_;
  std::unique_ptr<transport::TileClient> tiles_;
  std::unique_ptr<transport::Topic<fleetloc_VehiclePose>> pose_topic_;
  std::unique_ptr<transport::Topic<fleetloc_VehicleHealth>> health_topic_;
  std::unique_ptr<transport::Topic<fleetloc_TileUpdate>> update_topic_;
  std::unique_ptr<transport::VehicleStreamWriter<fleetloc_VehiclePose>> pose_writer_;
  std::unique_ptr<transport::VehicleStreamWriter<fleetloc_VehicleHealth>> health_writer_;
  std::unique_ptr<transport::Reader<fleetloc_TileUpdate>> update_reader_;
  mosaic::MosaicLayout layout_;
  std::unique_ptr<MapServerDirectory> map_servers_;
  bool map_server_reachable_ = true;
  std::unique_ptr<transport::DdsTileLoader> loader_;
  std::shared_ptr<mosaic::TileCache> tile_cache_;
  std::unique_ptr<mosaic::MosaicView> view_;
  std::unique_ptr<AgentRelocalizer> relocalizer_;
  metrics::Histogram tile_round_trip_{metrics::Histogram::LatencyBoundsS()};
  // Live vehicles: the ROS 2 bridge and capture → pose-on-the-wire latencies (host clock; the
  // last 10,000 frames).
  std::unique_ptr<RosBridge> ros_;
  CaptureLatency capture_latency_;
};

}  // namespace fleetloc::tracker_agent
