// Local distortion of a built mosaic against the true floor image: a grid of patches of the built
// mosaic is registered (normalized NCC, sub-pixel peak) against the truth around the same map
// position; the displacements give the RMS and largest error and, fitted by a similarity
// transform, the mosaic's global scale and rotation error and what remains after removing them.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "base/status.h"

namespace fleetloc::mapping {

struct DistortionOptions {
  int patch_px = 64;            // square patches of the built mosaic …
  int spacing_px = 96;          // … on a grid with this step
  int search_px = 8;            // searched ± this around the nominal position in the truth
  int normalize_window_px = 7;  // local normalization before correlating (as the tracker does)
  double min_peak = 0.5;        // weaker correlation peaks are not counted
};

struct PatchDisplacement {
  Eigen::Vector2d center_px;        // patch centre (pixel coordinates of both images)
  Eigen::Vector2d displacement_px;  // where its content lies in the truth minus where it should
  double peak = 0.0;
};

struct DistortionReport {
  std::vector<PatchDisplacement> patches;
  int patches_tried = 0;  // fully mapped patches on the grid
  double rms_px = 0.0;    // of |displacement|
  double max_px = 0.0;
  // Similarity fit truth ≈ s·R(θ)·built + t over the patch centres (image axes, v down):
  double scale_error = 0.0;              // s − 1
  double rotation_rad = 0.0;             // θ, counter-clockwise in map (y up)
  Eigen::Vector2d translation_px{0, 0};  // t at the patches' centroid
  double residual_rms_px = 0.0;          // after removing the similarity: the local distortion
  double residual_max_px = 0.0;
};

// `built` and `truth` are CV_8UC1 on the same pixel grid (equal sizes; pixel (u, v) of both shows
// the same map point); 0 in `built` marks unmapped pixels, and only fully mapped patches are
// measured. InvalidInput when the sizes differ or fewer than 3 patches match.
Result<DistortionReport> MeasureDistortion(const cv::Mat& built, const cv::Mat& truth,
                                           const DistortionOptions& options = {});

}  // namespace fleetloc::mapping
