// Blending registered frames into a mosaic raster (docs/architecture.md): each frame is resampled
// into a float canvas over the bounding box of all footprints with feathered weights (falling to
// zero at the frame's border, so seams fade instead of stepping), optionally after fitting its gain
// and bias to what is already accumulated; the canvas is then read row by row as 8-bit gray.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/geotransform.h"

namespace fleetloc::mapping {

struct BlendOptions {
  // weight = (distance to the frame's border / half its shorter side) ^ feather_power
  double feather_power = 1.0;
  bool normalize_gain = true;   // fit each frame's gain and bias to the accumulated mosaic
  int min_gain_samples = 2000;  // overlapping pixels needed for that fit
  double min_gain = 0.5;        // fits outside [min_gain, max_gain] are not applied
  double max_gain = 2.0;
  double max_canvas_mb = 4096.0;  // two floats per canvas pixel
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const BlendOptions& options);

// A level-0 pixel grid in map (docs/formats.md).
struct Canvas {
  geometry::Geotransform geo;
  int width_px = 0;
  int height_px = 0;
};

// The smallest grid at the camera's resolution, with its origin on a multiple of the resolution,
// that covers every frame's footprint. InvalidInput when it would need more than max_canvas_mb
// (the message states the size) or there are no frames.
Result<Canvas> CanvasFor(const std::vector<geometry::Pose2>& camera_in_map,
                         const geometry::CameraModel& camera, const BlendOptions& options);

class MosaicBlender {
 public:
  // Allocates the float canvas: 8 bytes per pixel (weighted sum and weight).
  MosaicBlender(const Canvas& canvas, const geometry::CameraModel& camera,
                const BlendOptions& options);

  // Adds a CV_8UC1 frame of the camera's size seen from camera_ground pose `camera_in_map`.
  // Returns the gain applied to it (1 when no fit was possible or wanted).
  double Add(const cv::Mat& frame, const geometry::Pose2& camera_in_map);

  // Row v of the mosaic: the weighted mean rounded and clamped to [1, 255], 0 where no frame
  // reached (unmapped). `out` holds exactly width_px pixels.
  void Row(int v, std::span<std::uint8_t> out) const;

  const Canvas& canvas() const { return canvas_; }
  std::size_t canvas_bytes() const { return 2 * sum_.total() * sizeof(float); }

 private:
  // Canvas pixel index relative to roi's top-left → frame pixel index (for ResampleAffine).
  cv::Matx23d CanvasToFrame(const geometry::Pose2& camera_in_map, const cv::Rect& roi) const;
  // The canvas pixels the frame's footprint can touch (clipped to the canvas).
  cv::Rect FootprintRoi(const geometry::Pose2& camera_in_map) const;
  // Least-squares gain and bias taking `values` to the accumulated mean over `roi`; {1, 0} when
  // the overlap is too small or the gain is out of range.
  cv::Vec2d FitGain(const cv::Mat& values, const cv::Mat& weights, const cv::Rect& roi) const;

  Canvas canvas_;
  geometry::CameraModel camera_;
  BlendOptions options_;
  cv::Mat feather_;  // CV_32F weight of each frame pixel
  cv::Mat sum_;      // CV_32F Σ w·value
  cv::Mat weight_;   // CV_32F Σ w
};

}  // namespace fleetloc::mapping
