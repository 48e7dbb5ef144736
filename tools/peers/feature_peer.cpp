// Detect, describe, ratio-test matching, RANSAC similarity; ORB and SIFT parameters.
#include "peers/feature_peer.h"

#include <cmath>
#include <opencv2/calib3d.hpp>

namespace fleetloc::peers {
namespace {

struct Matched {
  std::vector<cv::Point2f> frame_px;
  std::vector<cv::Point2f> view_px;
};

// Pairs whose best match is clearly better than the second best (Lowe's ratio test).
Matched RatioMatches(const std::vector<std::vector<cv::DMatch>>& knn,
                     const std::vector<cv::KeyPoint>& frame_keys,
                     const std::vector<cv::KeyPoint>& view_keys, double ratio) {
  Matched matched;
  for (const std::vector<cv::DMatch>& pair : knn) {
    if (pair.size() < 2 || pair[0].distance >= ratio * pair[1].distance) continue;
    matched.frame_px.push_back(frame_keys[pair[0].queryIdx].pt);
    matched.view_px.push_back(view_keys[pair[0].trainIdx].pt);
  }
  return matched;
}

double InlierRms(const Matched& matched, const std::vector<uchar>& inlier, const cv::Matx23d& m) {
  double sum_sq = 0.0;
  int count = 0;
  for (size_t i = 0; i < inlier.size(); ++i) {
    if (!inlier[i]) continue;
    const cv::Point2f& f = matched.frame_px[i];
    const cv::Vec2d predicted = m * cv::Vec3d(f.x, f.y, 1.0);
    sum_sq += std::pow(predicted[0] - matched.view_px[i].x, 2) +
              std::pow(predicted[1] - matched.view_px[i].y, 2);
    ++count;
  }
  return count > 0 ? std::sqrt(sum_sq / count) : 0.0;
}

}  // namespace

FeaturePeer::FeaturePeer(std::string name, cv::Ptr<cv::Feature2D> features, int norm,
                         const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                         const FeatureOptions& feature_options, const PeerOptions& options)
    : PeerLocalizer(camera, mosaic, feature_options.view_margin_px, options),
      name_(std::move(name)),
      features_(std::move(features)),
      matcher_(norm),
      feature_options_(feature_options) {}

std::optional<Registration> FeaturePeer::Register(const cv::Mat& frame, const cv::Mat& view) {
  std::vector<cv::KeyPoint> frame_keys, view_keys;
  cv::Mat frame_descriptors, view_descriptors;
  features_->detectAndCompute(frame, cv::noArray(), frame_keys, frame_descriptors);
  features_->detectAndCompute(view, cv::noArray(), view_keys, view_descriptors);
  if (frame_keys.size() < 2 || view_keys.size() < 2) return std::nullopt;
  std::vector<std::vector<cv::DMatch>> knn;
  matcher_.knnMatch(frame_descriptors, view_descriptors, knn, 2);
  const Matched matched = RatioMatches(knn, frame_keys, view_keys, feature_options_.ratio);
  const int min_inliers = feature_options_.min_inliers;
  if (static_cast<int>(matched.frame_px.size()) < min_inliers) return std::nullopt;
  std::vector<uchar> inlier;
  const cv::Mat similarity = cv::estimateAffinePartial2D(
      matched.frame_px, matched.view_px, inlier, cv::RANSAC, feature_options_.ransac_threshold_px,
      feature_options_.ransac_max_iterations, feature_options_.ransac_confidence,
      feature_options_.refine_iterations);
  const int inliers = cv::countNonZero(inlier);
  if (similarity.empty() || inliers < min_inliers) return std::nullopt;
  Registration registration;
  registration.frame_to_view = cv::Matx23d(similarity);
  registration.matches = static_cast<int>(matched.frame_px.size());
  registration.inliers = inliers;
  registration.rms_residual_px = InlierRms(matched, inlier, registration.frame_to_view);
  return registration;
}

// ORB: 1500 features over 3 levels, FAST threshold 5 (OpenCV: 8 levels, threshold 20). Scale is
// fixed by calibration, so a deep pyramid only thins the full-resolution keypoints; a low FAST
// threshold keeps low-contrast floors trackable (brick photo, 160×120 frames: 31/32 frames
// registered at threshold 5, 12/32 at 10, 4/32 with OpenCV's defaults) at the same accuracy on
// well-textured ones. Patch and border 31 as OpenCV's defaults.
OrbPeer::OrbPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                 const FeatureOptions& feature_options, const PeerOptions& options)
    : FeaturePeer("orb",
                  cv::ORB::create(/*nfeatures=*/1500, /*scaleFactor=*/1.2f, /*nlevels=*/3,
                                  /*edgeThreshold=*/31, /*firstLevel=*/0, /*WTA_K=*/2,
                                  cv::ORB::HARRIS_SCORE, /*patchSize=*/31, /*fastThreshold=*/5),
                  cv::NORM_HAMMING, camera, mosaic, feature_options, options) {}

// SIFT: up to 1500 features, OpenCV's defaults otherwise except a contrast threshold of 0.02
// (default 0.04) for more keypoints on low-contrast floors (brick photo: ~10 % more inliers, same
// accuracy).
SiftPeer::SiftPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
                   const FeatureOptions& feature_options, const PeerOptions& options)
    : FeaturePeer("sift",
                  cv::SIFT::create(/*nfeatures=*/1500, /*nOctaveLayers=*/3,
                                   /*contrastThreshold=*/0.02, /*edgeThreshold=*/10,
                                   /*sigma=*/1.6),
                  cv::NORM_L2, camera, mosaic, feature_options, options) {}

PeerOptions OrbPeer::DefaultOptions() { return WithMeasurementSigma(0.25); }

PeerOptions SiftPeer::DefaultOptions() { return WithMeasurementSigma(0.05); }

}  // namespace fleetloc::peers
