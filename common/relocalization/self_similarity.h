// Self-similarity report for a floor (issue 17): places where the floor repeats itself so closely
// that a frame there cannot be relocalized unambiguously. Frame-sized crops of the mosaic on a
// grid are searched with the dense place search; a crop whose best distinct alternative reaches
// the acceptance ratio of its best is ambiguous, and the report names it and its twin. Run when
// the dense search is made, so a floor with repeated content is reported before a vehicle is lost
// on it. Pure: reads the mosaic through a RasterSource.
#pragma once

#include <functional>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "mosaic/raster_source.h"
#include "relocalization/dense_place_search.h"

namespace fleetloc::relocalization {

struct SelfSimilarityOptions {
  int grid = 3;                  // crops per side (grid × grid), spread where a frame fits
  double ambiguous_ratio = 0.6;  // second ≥ this × best: ambiguous (RelocalizerOptions' gate)
};

struct SimilarPlace {
  geometry::Pose2 place;  // camera_ground of the crop
  geometry::Pose2 twin;   // the best peak that is not the crop's own place
  double own = 0, twin_correlation = 0;
};

struct SelfSimilarityReport {
  int sampled = 0;
  std::vector<SimilarPlace> ambiguous;
};

// InvalidInput when the mosaic is smaller than a frame or the options are out of range.
// `progress`, when given, is called after each crop with (crops done, crops in all); returning
// false cancels the search (Internal "self-similarity: cancelled").
Result<SelfSimilarityReport> FindSelfSimilarity(
    const DensePlaceSearch& search, mosaic::RasterSource& mosaic,
    const geometry::CameraModel& camera, const SelfSimilarityOptions& options,
    const std::function<bool(int done, int total)>& progress = {});

}  // namespace fleetloc::relocalization
