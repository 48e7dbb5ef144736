// Peer factory.
#include "peers/make_peer.h"

#include "peers/ecc_peer.h"
#include "peers/feature_peer.h"
#include "peers/phase_correlation_peer.h"

namespace fleetloc::peers {

const std::vector<std::string>& PeerNames() {
  static const std::vector<std::string> names{"orb", "sift", "ecc", "phase"};
  return names;
}

std::unique_ptr<tracking::FrameLocalizer> MakePeer(const std::string& name,
                                                   const geometry::CameraModel& camera,
                                                   mosaic::RasterSource* mosaic) {
  if (name == "orb") return std::make_unique<OrbPeer>(camera, mosaic);
  if (name == "sift") return std::make_unique<SiftPeer>(camera, mosaic);
  if (name == "ecc") return std::make_unique<EccPeer>(camera, mosaic);
  if (name == "phase") return std::make_unique<PhaseCorrelationPeer>(camera, mosaic);
  return nullptr;
}

}  // namespace fleetloc::peers
