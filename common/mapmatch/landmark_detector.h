// Landmark detection from a forward-camera image (paper 001 §6.1, docs/architecture.md):
// near-vertical edges (Canny + probabilistic Hough, kept when they point at the nadir vanishing
// point), their lowest points refined to sub-pixel, back-projected to the floor by inverse
// perspective mapping. The result is floor points in base_link, many of them outliers (clutter,
// edges that end above the floor); the robust map fit sorts them out.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "base/status.h"
#include "mapmatch/forward_camera.h"
#include "mapmatch/undistorted_view.h"
#include "mapmatch/vertical_edge.h"

namespace fleetloc::mapmatch {

struct LandmarkDetectorOptions {
  double smoothing_sigma_px = 1.0;  // Gaussian blur before the gradient; 0 = none
  double canny_low = 20.0;          // Canny hysteresis thresholds on the L2 gradient of the
  double canny_high = 50.0;         // smoothed image (3×3 Sobel units)
  double hough_rho_px = 1.0;
  double hough_theta_rad = M_PI / 360;
  int hough_votes = 15;
  double min_line_length_px = 30.0;      // vertical edges, after joining their Hough pieces
  double min_boundary_length_px = 12.0;  // floor boundaries, which may be short (<= the above)
  double max_line_gap_px = 4.0;
  double max_vertical_deviation_rad = 0.035;  // segment vs the downward direction at its middle
  double min_boundary_angle_rad = 0.25;       // floor boundaries cross vertical edges this steeply
  double merge_distance_px = 3.0;             // segments this close to an edge's line join it
  double merge_gap_px = 12.0;                 // ... when they overlap or continue it within this
  EdgeRefinement refinement;
  double min_range_m = 0.3;   // floor points nearer or farther than these (from the camera,
  double max_range_m = 12.0;  // horizontally) are dropped
  // Quality: precision weight 1 / (1 + (sigma / reference_sigma)²) times edge support
  // min(1, length / full_support_length).
  double foot_sigma_px = 0.5;  // assumed foot error, for sigma_m
  double reference_sigma_m = 0.05;
  double full_support_length_px = 120.0;
};

// InvalidInput "landmark detector: <field> ..." naming the first bad field.
Status Validate(const LandmarkDetectorOptions& options);

// One floor point measurement.
struct FloorPointDetection {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();    // on the floor, base_link (metres)
  Eigen::Vector2d foot_px = Eigen::Vector2d::Zero();  // the edge's lowest point, ideal pixels
  double edge_length_px = 0.0;
  double range_m = 0.0;  // horizontal distance from the camera
  double sigma_m = 0.0;  // position error along the viewing ray for foot_sigma_px of foot error
  double quality = 0.0;  // (0, 1]
};

class LandmarkDetector {
 public:
  // Precomputes the undistortion maps. InvalidInput for invalid options.
  static Result<LandmarkDetector> Create(const ForwardCamera& camera,
                                         const LandmarkDetectorOptions& options);

  // `image`: 8-bit gray or BGR, of the camera's size. InvalidInput for an empty image, another
  // size or another type.
  Result<std::vector<FloorPointDetection>> Detect(const cv::Mat& image) const;

  // The refined vertical edges of an image (ideal pixels), before back-projection.
  Result<std::vector<EdgeSegment>> DetectEdges(const cv::Mat& image) const;

  const ForwardCamera& camera() const { return camera_; }

 private:
  LandmarkDetector(const ForwardCamera& camera, const LandmarkDetectorOptions& options);
  Status CheckImage(const cv::Mat& image) const;
  // The undistorted, smoothed gray canvas (CV_32FC1, see UndistortedView).
  cv::Mat IdealImage(const cv::Mat& image) const;
  // NadirVanishingPoint in canvas pixels.
  Eigen::Vector3d CanvasNadirVanishingPoint() const;
  std::optional<FloorPointDetection> ToFloor(const EdgeSegment& edge) const;

  ForwardCamera camera_;
  LandmarkDetectorOptions options_;
  UndistortedView view_;
};

}  // namespace fleetloc::mapmatch
