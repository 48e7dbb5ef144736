// ECC registration over a small image pyramid.
#include "peers/ecc_peer.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace fleetloc::peers {
namespace {

// A warp between level-k indices moved to level k−1: cv::pyrDown centres output index p on
// input index 2p, so only the translation doubles.
cv::Mat UpLevel(const cv::Mat& warp) {
  cv::Mat up = warp.clone();
  up.col(2) *= 2.0;
  return up;
}

// The view pixels the mosaic covers: the renderer leaves the rest 0 (a floor photograph has no
// pure black pixel worth keeping), shrunk by the smoothing and interpolation footprint so that
// the edge of the covered region does not look like texture to ECC.
cv::Mat MosaicMask(const cv::Mat& view) {
  cv::Mat mask = view > 0;
  cv::erode(mask, mask, cv::Mat(), cv::Point(-1, -1), /*iterations=*/3);
  return mask;
}

}  // namespace

EccPeer::EccPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                 const EccOptions& ecc_options, const PeerOptions& options)
    : PeerLocalizer(camera, mosaic, /*view_margin_px=*/0, options), ecc_options_(ecc_options) {}

std::optional<Registration> EccPeer::Register(const cv::Mat& frame, const cv::Mat& view) {
  std::vector<cv::Mat> frames{frame}, views{view}, masks{MosaicMask(view)};
  for (int level = 1; level < ecc_options_.pyramid_levels; ++level) {
    frames.emplace_back();
    views.emplace_back();
    masks.emplace_back();
    cv::pyrDown(frames[level - 1], frames[level]);
    cv::pyrDown(views[level - 1], views[level]);
    cv::resize(masks[level - 1], masks[level], views[level].size(), 0, 0, cv::INTER_NEAREST);
  }
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                  ecc_options_.max_iterations, ecc_options_.epsilon);
  // findTransformECC(template, input, W): input(W·x) ≈ template(x), so W maps frame → view.
  cv::Mat warp = cv::Mat::eye(2, 3, CV_32F);
  double correlation = 0.0;
  for (int level = ecc_options_.pyramid_levels - 1; level >= 0; --level) {
    correlation = cv::findTransformECC(frames[level], views[level], warp, cv::MOTION_EUCLIDEAN,
                                       criteria, masks[level], ecc_options_.gauss_filter_size);
    if (level > 0) warp = UpLevel(warp);
  }
  if (correlation < ecc_options_.min_correlation) return std::nullopt;
  Registration registration;
  warp.convertTo(warp, CV_64F);
  registration.frame_to_view = cv::Matx23d(warp);
  registration.matches = 1;
  registration.inliers = 1;
  return registration;
}

PeerOptions EccPeer::DefaultOptions() { return WithMeasurementSigma(0.05); }

}  // namespace fleetloc::peers
