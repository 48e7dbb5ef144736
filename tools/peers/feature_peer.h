// Feature-based peers: keypoints and descriptors on the frame and on the predicted view (grown by
// a search margin), nearest-neighbour matching with Lowe's ratio test, and a RANSAC similarity
// (cv::estimateAffinePartial2D) frame → view. OrbPeer and SiftPeer differ only in the detector.
#pragma once

#include <opencv2/features2d.hpp>

#include "peers/peer_localizer.h"

namespace fleetloc::peers {

struct FeatureOptions {
  int view_margin_px = 48;           // search margin around the frame: fleetloc's max radius
  double ratio = 0.8;                // Lowe's ratio test: best < ratio × second best
  double ransac_threshold_px = 2.0;  // reprojection threshold of an inlier
  int ransac_max_iterations = 2000;
  double ransac_confidence = 0.995;
  int refine_iterations = 10;  // Levenberg–Marquardt on the inliers after RANSAC
  int min_inliers = 12;        // a 2-point model: random matches rarely agree on 12
};

class FeaturePeer : public PeerLocalizer {
 public:
  std::string name() const override { return name_; }

 protected:
  // `features` detects and describes; `norm` is the descriptor distance (NORM_HAMMING, NORM_L2).
  FeaturePeer(std::string name, cv::Ptr<cv::Feature2D> features, int norm,
              const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
              const FeatureOptions& features_options, const PeerOptions& options);

  std::optional<Registration> Register(const cv::Mat& frame, const cv::Mat& view) override;

 private:
  std::string name_;
  cv::Ptr<cv::Feature2D> features_;
  cv::BFMatcher matcher_;
  FeatureOptions feature_options_;
};

// ORB (oriented FAST + rotated BRIEF), Hamming matching.
class OrbPeer : public FeaturePeer {
 public:
  // PeerOptions with measurement_sigma_px = 0.25 px: integer keypoints,
  // ~0.1 px for the frame position.
  static PeerOptions DefaultOptions();
  OrbPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
          const FeatureOptions& feature_options = {},
          const PeerOptions& options = DefaultOptions());
};

// SIFT (OpenCV ≥ 4.4 main modules), L2 matching.
class SiftPeer : public FeaturePeer {
 public:
  // PeerOptions with measurement_sigma_px = 0.05 px: ~0.02 px for the frame position.
  static PeerOptions DefaultOptions();
  SiftPeer(const geometry::CameraModel& camera, mosaic::RasterSource* mosaic,
           const FeatureOptions& feature_options = {},
           const PeerOptions& options = DefaultOptions());
};

}  // namespace fleetloc::peers
