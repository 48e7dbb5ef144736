// The changed-floor scene's patches as a vehicle sends them over DDS, and the map region around
// the change: shared by the re-mapping, map-server fault and agent tile-update tests.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <string>
#include <thread>

#include "mapping/changed_floor_scene.h"
#include "mosaic/tile_codec.h"
#include "transport/patch_client.h"

namespace fleetloc::testing {

using Scene = mapping::testing::ChangedFloorScene;

// `p` as a vehicle sends it, numbered `sequence`, with its quality (0.9 when it has none) and a
// stamp of 100 + sequence s. `mosaic_id` empty: whatever mosaic the server serves.
inline transport::PatchToSend ToSend(const mapping::Patch& p, uint64_t sequence,
                                     const std::string& mosaic_id = "") {
  transport::PatchToSend out;
  out.sequence = sequence;
  out.stamp_s = 100.0 + static_cast<double>(sequence);
  out.mosaic_id = mosaic_id;
  out.mosaic_version = 1;
  out.pose = p.pose;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(out.covariance) = p.covariance;
  out.quality = p.quality > 0 ? static_cast<float>(p.quality) : 0.9f;
  out.resolution_m = Scene::kRes;
  out.png = *mosaic::EncodeTile(p.image);
  return out;
}

// The scene's patch at pixel `centre`, reported off by `error` (see ToSend).
inline transport::PatchToSend ScenePatch(const Scene& scene, uint64_t sequence, cv::Point centre,
                                         const geometry::Pose2& error,
                                         const std::string& mosaic_id = "") {
  return ToSend(scene.PatchAt(centre, error), sequence, mosaic_id);
}

// "x0,y0,x1,y1" in map metres around the change, as `fleetctl remap --region` takes it.
inline std::string RegionAroundChange(const Scene& scene) {
  const Eigen::Vector2d a = scene.geo.PixelToMap({400, 500}), b = scene.geo.PixelToMap({600, 350});
  return std::to_string(a.x()) + "," + std::to_string(a.y()) + "," + std::to_string(b.x()) + "," +
         std::to_string(b.y());
}

// Sends `patch`, retrying for up to 10 s: a patch writer waits at most 0.1 s for room in the
// reliable history (so a vehicle never stalls), and under load back-to-back large patches can
// time out once — the agent's outbox retries the same way. True when one send was accepted.
inline bool SendPatch(transport::PatchClient& client, const transport::PatchToSend& patch) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!client.Send(patch).ok()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return true;
}

}  // namespace fleetloc::testing
