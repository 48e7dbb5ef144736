// The predicted mosaic view of a frame-aligned rectangle: the mosaic resampled into the frame's
// pixel grid and orientation as the camera at a predicted pose would see it. Shared by the
// template matcher and by the OpenCV peer localizers.
#pragma once

#include <opencv2/core.hpp>

#include "mosaic/raster_source.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/normalized_mosaic.h"

namespace fleetloc::tracking {

// Renders `frame_rect` (frame pixels, may extend beyond the frame) through `warp` (frame →
// mosaic pixels of pyramid level `level`): view pixel (i, j) shows the frame point
// frame_rect.tl() + (i, j) + 0.5, bilinearly interpolated. Returns a CV_8UC1 image of
// frame_rect's size; mosaic pixels outside the mosaic are 0. `mosaic` must not be null.
cv::Mat RenderPredictedView(mosaic::RasterSource* mosaic, const cv::Rect& frame_rect,
                            const FrameMosaicWarp& warp, int level = 0);

// The same view as CV_32F, resampled by the tracker's own small-patch kernel
// (imaging/fast_patch.h).
cv::Mat RenderPredictedViewFloat(mosaic::RasterSource* mosaic, const cv::Rect& frame_rect,
                                 const FrameMosaicWarp& warp, int level);

// The view of `level_rect` (pixels of frame level `level`) whose pixels are the mosaic averaged
// over the 2^level × 2^level level-0 pixels about each one's centre, as the frame's own levels
// average its pixels, as CV_32F; `warp` maps level-0 frame pixels to level-0 mosaic pixels. The
// average is taken over a square aligned with the mosaic's axes, then sampled bilinearly at the
// pixel's centre: where the frame's axes are parallel to the mosaic's this is the level-0 view
// (RenderPredictedViewFloat) averaged down, to float rounding; at other headings the squares
// differ by their turn, with the same centre and the same second moments (a blur of the same
// size). It costs a box filter of the level-0 block and 4^-level of the samples.
cv::Mat RenderAreaAveragedView(mosaic::RasterSource* mosaic, const cv::Rect& level_rect,
                               const FrameMosaicWarp& warp, int level);

// The same view of the locally normalized mosaic, as CV_32F, resampled by the tracker's own
// small-patch kernel (fast on the template-sized views of the hot loop; see imaging/fast_patch.h).
cv::Mat RenderNormalizedView(NormalizedMosaic* mosaic, const cv::Rect& frame_rect,
                             const FrameMosaicWarp& warp, int level);

}  // namespace fleetloc::tracking
