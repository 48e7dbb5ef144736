// Renders the rectified top view a real downward camera would capture at a given base_link pose
// over a mosaic floor: area-sensor sampling of the floor (with grain the mosaic lacks), dust, tyre
// marks and debris on the floor, the vehicle's shadow, uneven lighting, lens
// and motion blur, vignetting, sensor noise, response curve, gain and bias, 8-bit output.
//
// Image pixel convention (the same as the mosaic's, docs/formats.md): pixel (i, j) covers
// [i, i + 1) × [j, j + 1) in continuous image coordinates; its centre is (i + 0.5, j + 0.5).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

#include "geometry/camera_model.h"
#include "mosaic/raster_source.h"
#include "sim/floor_dust.h"
#include "sim/floor_grain.h"
#include "sim/floor_marks.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

struct RenderedFrame {
  cv::Mat image;      // CV_8UC1, camera width × height
  double gain = 1.0;  // this frame's sensor draw
  double bias_dn = 0.0;
  double dust_coverage = 0.0;   // share of pixels inside a dust blob
  double marks_coverage = 0.0;  // share of pixels under a tyre mark or debris
};

class CameraRenderer {
 public:
  // `floor` (its level 0) must outlive the renderer. Beyond the floor's edge the renderer shows
  // the floor mirrored at that edge (unmapped floor of the same kind, not a black void).
  CameraRenderer(mosaic::RasterSource* floor, geometry::CameraModel camera, RenderOptions options,
                 std::uint64_t seed);

  // The frame seen with base_link at `base_in_map`. `image_velocity_px_s` is the floor's velocity
  // across the image (for motion blur; the frame time is the middle of the exposure).
  // Deterministic in (seed, frame_index, pose).
  RenderedFrame Render(const geometry::Pose2& base_in_map,
                       const Eigen::Vector2d& image_velocity_px_s, std::uint64_t frame_index);

  // The floor as an ideal area sensor sees it (no other effect): CV_32FC1 in DN, the camera's
  // size grown by `margin_px` on every side (pixel (0, 0) is image pixel (-margin, -margin)).
  cv::Mat RenderFloor(const geometry::Pose2& camera_in_map, int margin_px);

  // Continuous image coordinates → continuous level-0 mosaic pixel coordinates, for base_link at
  // `base_in_map` (an affine map; the geometric ground truth of a rendered frame).
  Eigen::Vector2d ImageToMosaic(const geometry::Pose2& base_in_map,
                                const Eigen::Vector2d& uv) const;

  const geometry::CameraModel& camera() const { return camera_; }

 private:
  // Image coordinates → map metres as a 2×3 affine matrix, for the camera at `camera_in_map`.
  Eigen::Matrix<double, 2, 3> ImageToMap(const geometry::Pose2& camera_in_map) const;
  // Level-0 pixels of `rect`, the floor mirrored at its edges where rect leaves it.
  cv::Mat ReadMirrored(const cv::Rect& rect);
  // The vehicle's shadow on frame `frame_index` (empty when off).
  cv::Mat Shadow(cv::Size size, std::uint64_t frame_index) const;

  mosaic::RasterSource* floor_;
  geometry::CameraModel camera_;
  RenderOptions options_;
  std::uint64_t seed_;
  FloorGrain grain_;
  FloorDust dust_;
  FloorMarks marks_;
  cv::Mat vignetting_;
};

}  // namespace fleetloc::sim
