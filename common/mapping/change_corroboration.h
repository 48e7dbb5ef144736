// Whether a patch's change of the floor is seen by more than one vehicle. A single vehicle (a
// faulty or compromised one) can send a patch that registers and whose change looks plausible —
// real floor around a forged marking. With corroboration on, the changed blocks of an admitted
// patch are folded only where the admitted patches of at least `min_vehicles` distinct vehicles
// (the sender included) show the same new floor there.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "geometry/pose2.h"

namespace fleetloc::mapping {

// An admitted patch as the corroboration sees it.
struct ObservedChange {
  const cv::Mat* image = nullptr;  // CV_8UC1, level-0 resolution
  geometry::Pose2 pose;            // registered camera_ground (image centre) in map
  std::string vehicle_id;
  std::vector<cv::Rect> changed_blocks;  // patch pixels where it differs from the mosaic
};

struct CorroborationOptions {
  int min_vehicles = 1;                 // 1: no corroboration needed
  double agree_ncc = 0.6;               // two views of a block agree at or above this ZNCC
  double min_confirmed_fraction = 0.5;  // of a patch's changed blocks
};

// Per input: true when its change is corroborated (always when min_vehicles <= 1 or it has no
// changed blocks). `resolution_m`: metres per pixel of every image.
std::vector<bool> CorroborateChanges(const std::vector<ObservedChange>& changes,
                                     double resolution_m, const CorroborationOptions& options);

// The affine map from pixel indices of an image of `from_size` at `from` to pixel indices of an
// image of `to_size` at `to` (both camera_ground poses in map, docs/formats.md), for warpAffine
// with WARP_INVERSE_MAP when rendering the `to` image in the `from` image's grid.
cv::Matx23d PatchToPatch(cv::Size from_size, const geometry::Pose2& from, cv::Size to_size,
                         const geometry::Pose2& to, double resolution_m);

}  // namespace fleetloc::mapping
