// Self-similarity report: dense searches of frame-sized crops of the mosaic (see
// self_similarity.h).
#include "relocalization/self_similarity.h"

#include <Eigen/Geometry>
#include <cmath>

namespace fleetloc::relocalization {
namespace {

// The camera pose whose frame is exactly the mosaic crop at `rect` (level 0): heading π/2 puts
// the image's top toward map +y (the mosaic's top) and its left toward map −x.
geometry::Pose2 CropPose(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
                         const cv::Rect& rect) {
  const Eigen::Vector2d centre_px(rect.x + camera.cx_px, rect.y + camera.cy_px);
  const Eigen::Vector2d at = layout.geo.PixelToMap(centre_px);
  const Eigen::Vector2d offset =
      Eigen::Rotation2Dd(M_PI / 2) * camera.PixelToGround({camera.cx_px, camera.cy_px});
  return {at.x() - offset.x(), at.y() - offset.y(), M_PI / 2};
}

}  // namespace

Result<SelfSimilarityReport> FindSelfSimilarity(
    const DensePlaceSearch& search, mosaic::RasterSource& mosaic,
    const geometry::CameraModel& camera, const SelfSimilarityOptions& options,
    const std::function<bool(int done, int total)>& progress) {
  if (options.grid < 1 || options.grid > 32)
    return InvalidInput("self-similarity: grid must be 1..32");
  if (!(options.ambiguous_ratio > 0.0 && options.ambiguous_ratio < 1.0))
    return InvalidInput("self-similarity: ambiguous_ratio must be in (0, 1)");
  const mosaic::MosaicLayout& layout = mosaic.layout();
  const int spare_x = layout.width_px - camera.width_px;
  const int spare_y = layout.height_px - camera.height_px;
  if (spare_x < 0 || spare_y < 0)
    return InvalidInput("self-similarity: the mosaic is smaller than a frame");
  SelfSimilarityReport report;
  for (int i = 0; i < options.grid; ++i) {
    for (int j = 0; j < options.grid; ++j) {
      const cv::Rect rect((2 * i + 1) * spare_x / (2 * options.grid),
                          (2 * j + 1) * spare_y / (2 * options.grid), camera.width_px,
                          camera.height_px);
      const geometry::Pose2 place = CropPose(layout, camera, rect);
      const cv::Mat crop = mosaic.ReadBlock(0, rect);
      std::vector<DensePeak> peaks = search.Search(crop);
      // The best place distinct from the crop's own at the refine level: a twin on a weak floor
      // need not be among the coarse peaks.
      peaks.push_back(search.Alternative({crop}, {geometry::Pose2{}}, place));
      ++report.sampled;
      // The crop's own place, and the best peak distinct from it.
      const DensePeak own{place, 0.0};
      double own_correlation = 0.0;
      const DensePeak* twin = nullptr;
      for (const DensePeak& p : peaks) {
        if (!search.Distinct(p, {own})) {
          own_correlation = std::max(own_correlation, p.correlation);
        } else if (twin == nullptr || p.correlation > twin->correlation) {
          twin = &p;
        }
      }
      if (twin && twin->correlation >= options.ambiguous_ratio * own_correlation) {
        report.ambiguous.push_back(
            {place, twin->camera_in_map, own_correlation, twin->correlation});
      }
      if (progress && !progress(report.sampled, options.grid * options.grid))
        return Internal("self-similarity: cancelled");
    }
  }
  return report;
}

}  // namespace fleetloc::relocalization
