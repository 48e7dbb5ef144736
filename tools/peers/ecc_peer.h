// EccPeer: direct (intensity-based) registration by enhanced correlation coefficient
// maximisation (cv::findTransformECC, Euclidean motion) of the frame onto the same-size predicted
// view, coarse to fine from the identity. Only view pixels the mosaic covers count (ECC's input
// mask): without it, a frame near the mosaic's edge was fitted to the black beyond it and ECC
// diverged from a prediction 1 px off (stress suite, worn asphalt 640×480: lock 20–30 % without
// the mask, 100 % with it).
#pragma once

#include "peers/peer_localizer.h"

namespace fleetloc::peers {

struct EccOptions {
  // Coarse to fine: quarter, half, then full resolution. A third level widens ECC's basin
  // (gravel photo, 10 px prediction error: 16/16 frames converge with 3 levels, 14/16 with 2,
  // 11/16 with 1).
  int pyramid_levels = 3;
  int max_iterations = 100;   // per level
  double epsilon = 1e-6;      // stop when the correlation coefficient improves by less
  int gauss_filter_size = 5;  // smoothing ECC applies to both images
  // A converged correlation coefficient below this is a false fit (measured on three floor
  // photos: true fits ≥ 0.98, fits at a wrong place ≤ 0.2 when ECC converges at all). Under
  // heavy dust and vignetting (the stress suite's dusty condition) right fits correlate 0.13–0.55
  // and wrong ones 0.03–0.28: no gate separates them, and this one keeps ECC from most false
  // locks there at the cost of most right ones.
  double min_correlation = 0.5;
};

class EccPeer : public PeerLocalizer {
 public:
  // PeerOptions with measurement_sigma_px = 0.05 px: ~0.01–0.02 px for the frame position.
  static PeerOptions DefaultOptions();
  // `mosaic` must outlive the peer.
  EccPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
          const EccOptions& ecc_options = {}, const PeerOptions& options = DefaultOptions());
  std::string name() const override { return "ecc"; }

 protected:
  // Throws cv::Exception when ECC does not converge (caught by Track: the peer coasts).
  std::optional<Registration> Register(const cv::Mat& frame, const cv::Mat& view) override;

 private:
  EccOptions ecc_options_;
};

}  // namespace fleetloc::peers
