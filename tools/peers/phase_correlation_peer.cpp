// Windowed phase correlation frame → view.
#include "peers/phase_correlation_peer.h"

#include <opencv2/imgproc.hpp>

namespace fleetloc::peers {

PhaseCorrelationPeer::PhaseCorrelationPeer(const geometry::CameraModel& camera,
                                           mosaic::RasterSource* mosaic,
                                           const PhaseOptions& phase_options,
                                           const PeerOptions& options)
    : PeerLocalizer(camera, mosaic, /*view_margin_px=*/0, options), phase_options_(phase_options) {
  cv::createHanningWindow(window_, {camera.width_px, camera.height_px}, CV_64F);
}

std::optional<Registration> PhaseCorrelationPeer::Register(const cv::Mat& frame,
                                                           const cv::Mat& view) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(frame, mean, stddev);
  if (stddev[0] < phase_options_.min_frame_stddev) return std::nullopt;
  cv::Mat frame64, view64;
  frame.convertTo(frame64, CV_64F);
  view.convertTo(view64, CV_64F);
  double response = 0.0;
  // The shift d such that view(p + d) ≈ frame(p).
  const cv::Point2d shift = cv::phaseCorrelate(frame64, view64, window_, &response);
  if (!(response >= phase_options_.min_response)) return std::nullopt;
  Registration registration;
  registration.frame_to_view = cv::Matx23d(1, 0, shift.x, 0, 1, shift.y);
  registration.matches = 1;
  registration.inliers = 1;
  return registration;
}

PeerOptions PhaseCorrelationPeer::DefaultOptions() { return WithMeasurementSigma(0.2); }

}  // namespace fleetloc::peers
