// PhaseCorrelationPeer: translation-only registration by phase correlation (cv::phaseCorrelate
// with a Hanning window) of the frame against the same-size predicted view rendered with the
// odometry-predicted heading. The heading stays the prediction's.
#pragma once

#include "peers/peer_localizer.h"

namespace fleetloc::peers {

struct PhaseOptions {
  // Peak response of cv::phaseCorrelate (OpenCV 4.6: the correlation surface summed around the
  // peak) below which the shift is not trusted. Measured on three floor photos, 160×120 frames:
  // true matches give ≥ 0.54 up to 2° heading error (≥ 0.33 at 3°), frames of another place
  // ≤ 0.26.
  double min_response = 0.3;
  // Phase correlation whitens the spectrum, so even a featureless frame yields a confident-looking
  // peak (up to 0.55 on the brick photo): frames with less grey-level spread than this (standard
  // deviation) are not registered.
  double min_frame_stddev = 4.0;
};

class PhaseCorrelationPeer : public PeerLocalizer {
 public:
  // PeerOptions with measurement_sigma_px = 0.2 px: ~0.08 px for the frame position.
  static PeerOptions DefaultOptions();
  // `mosaic` must outlive the peer.
  PhaseCorrelationPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                       const PhaseOptions& phase_options = {},
                       const PeerOptions& options = DefaultOptions());
  std::string name() const override { return "phase"; }

 protected:
  std::optional<Registration> Register(const cv::Mat& frame, const cv::Mat& view) override;

 private:
  PhaseOptions phase_options_;
  cv::Mat window_;  // Hanning window of the frame's size, CV_64F
};

}  // namespace fleetloc::peers
