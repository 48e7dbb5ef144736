// Seamless blending of registered floor patches into level-0 mosaic tiles: each patch is resampled
// into the tile through its pose (one affine warp), weighted by a feather that falls to zero at the
// patch border (so no seam appears where a patch ends), photometrically matched to the mosaic
// (gain and bias), and either averaged with the mosaic (blend) or laid over it (replace).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/geotransform.h"
#include "geometry/pose2.h"

namespace fleetloc::mapping {

enum class BlendMode {
  kBlend,    // patches and mosaic averaged with equal weight where a patch is fully inside
  kReplace,  // patches replace the mosaic (the floor changed), feathered at their borders
};

struct PlacedPatch {
  cv::Mat image;         // CV_8UC1, level-0 resolution
  geometry::Pose2 pose;  // camera_ground (image centre) in map
  double gain = 1.0;     // mosaic ≈ gain · patch + bias
  double bias = 0.0;
};

// The feather weight of each pixel of a w × h patch: smoothstep of (distance to the border in
// pixels / feather_px), clipped to [0, 1]. CV_32F.
cv::Mat FeatherWeights(cv::Size size, double feather_px);

// The affine map from tile pixel index (j, i) to patch pixel index, for warpAffine with
// WARP_INVERSE_MAP: tile pixel centre → map (geo) → camera_ground (pose⁻¹) → patch pixel.
cv::Matx23d TileToPatch(const PlacedPatch& patch, cv::Point tile_origin_px,
                        const geometry::Geotransform& geo);

// Blends `patches` into `tile` (CV_8UC1 level-0 tile whose top-left pixel is `tile_origin_px`).
// Pixels no patch reaches are unchanged. `valid` (CV_8UC1, optional) marks mosaic pixels that
// exist; where none exists a patch pixel is taken as is in both modes.
cv::Mat BlendTile(const cv::Mat& tile, cv::Point tile_origin_px, const geometry::Geotransform& geo,
                  const std::vector<PlacedPatch>& patches, BlendMode mode, double feather_px);

// Gain and bias that map `patch` pixels onto `mosaic` pixels (same size, CV_8UC1; pixels where
// the mosaic is 0 are ignored): a robust line fit that ignores the pixels that disagree (changed
// floor). {1, 0} if fewer than 100 pixels overlap or the patch is flat.
std::pair<double, double> PhotometricFit(const cv::Mat& patch, const cv::Mat& mosaic);

}  // namespace fleetloc::mapping
