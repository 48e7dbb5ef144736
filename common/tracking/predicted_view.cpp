// Predicted mosaic view: read the covering block of the level, then one inverse-mapped warpAffine.
#include "tracking/predicted_view.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/imgproc.hpp>

#include "imaging/resample.h"

namespace fleetloc::tracking {

namespace {

// The mosaic block covering a view and the affine from view pixel index to block pixel index.
struct ViewSource {
  cv::Mat block;
  cv::Matx23d view_to_block;
};

using BlockReader = std::function<cv::Mat(int level, const cv::Rect& rect)>;

ViewSource CoveringBlock(const BlockReader& read, const cv::Rect& frame_rect,
                         const FrameMosaicWarp& warp, int level) {
  // Bounding box of the view's corners in the mosaic, with room for interpolation.
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector2d f(frame_rect.x + (corner & 1) * frame_rect.width,
                            frame_rect.y + (corner >> 1) * frame_rect.height);
    const Eigen::Vector2d m = warp(f);
    min_x = std::min(min_x, m.x());
    max_x = std::max(max_x, m.x());
    min_y = std::min(min_y, m.y());
    max_y = std::max(max_y, m.y());
  }
  const cv::Rect block_rect(static_cast<int>(std::floor(min_x)) - 2,
                            static_cast<int>(std::floor(min_y)) - 2,
                            static_cast<int>(std::ceil(max_x - min_x)) + 5,
                            static_cast<int>(std::ceil(max_y - min_y)) + 5);
  // View index (i, j) is frame point tl + (i, j) + 0.5; its block index is
  // warp(frame point) − 0.5 − block origin.
  const Eigen::Vector2d origin = warp(Eigen::Vector2d(frame_rect.x + 0.5, frame_rect.y + 0.5)) -
                                 Eigen::Vector2d(0.5 + block_rect.x, 0.5 + block_rect.y);
  return {read(level, block_rect), cv::Matx23d(warp.linear(0, 0), warp.linear(0, 1), origin.x(),
                                               warp.linear(1, 0), warp.linear(1, 1), origin.y())};
}

// The covering block of the mosaic's own pixels.
ViewSource RawCoveringBlock(mosaic::RasterSource* mosaic, const cv::Rect& frame_rect,
                            const FrameMosaicWarp& warp, int level) {
  return CoveringBlock([mosaic](int l, const cv::Rect& r) { return mosaic->ReadBlock(l, r); },
                       frame_rect, warp, level);
}

}  // namespace

cv::Mat RenderPredictedView(mosaic::RasterSource* mosaic, const cv::Rect& frame_rect,
                            const FrameMosaicWarp& warp, int level) {
  const ViewSource source = RawCoveringBlock(mosaic, frame_rect, warp, level);
  cv::Mat view;
  cv::warpAffine(source.block, view, source.view_to_block, frame_rect.size(),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT);
  return view;
}

cv::Mat RenderPredictedViewFloat(mosaic::RasterSource* mosaic, const cv::Rect& frame_rect,
                                 const FrameMosaicWarp& warp, int level) {
  const ViewSource source = RawCoveringBlock(mosaic, frame_rect, warp, level);
  return imaging::ResampleAffine(source.block, source.view_to_block, frame_rect.size());
}

cv::Mat RenderAreaAveragedView(mosaic::RasterSource* mosaic, const cv::Rect& level_rect,
                               const FrameMosaicWarp& warp, int level) {
  const int k = 1 << level;
  // The level-0 view of the pixels under level_rect, with k level-0 pixels to spare each side so
  // that every k × k average sampled lies inside the covering block.
  const cv::Rect frame_rect((level_rect.x - 1) * k, (level_rect.y - 1) * k,
                            (level_rect.width + 2) * k, (level_rect.height + 2) * k);
  const ViewSource source = RawCoveringBlock(mosaic, frame_rect, warp, 0);
  // averaged(m) = mean of block(m + a), a ∈ [0, k)², located at m + (k − 1) / 2.
  // Level pixel (j, i) is the centre of level-0 view pixels k·(j + 1) … k·(j + 1) + k − 1 of
  // frame_rect, i.e. view index k·(j + 1) + (k − 1) / 2; its average over the k × k pixels about
  // it is the k × k means' image (mean (y, x) over block rows y … y + k − 1 and columns x … x +
  // k − 1) at that index's block position less (k − 1) / 2.
  const cv::Matx23d& m = source.view_to_block;
  const double centre = k + 0.5 * (k - 1);
  const cv::Matx23d level_to_averaged(
      m(0, 0) * k, m(0, 1) * k, m(0, 0) * centre + m(0, 1) * centre + m(0, 2) - 0.5 * (k - 1),
      m(1, 0) * k, m(1, 1) * k, m(1, 0) * centre + m(1, 1) * centre + m(1, 2) - 0.5 * (k - 1));
  if (k == 2) return imaging::ResamplePairMeans(source.block, level_to_averaged, level_rect.size());
  return imaging::ResampleAffine(imaging::BoxAverage(source.block, k), level_to_averaged,
                                 level_rect.size());
}

cv::Mat RenderNormalizedView(NormalizedMosaic* mosaic, const cv::Rect& frame_rect,
                             const FrameMosaicWarp& warp, int level) {
  const ViewSource source =
      CoveringBlock([mosaic](int l, const cv::Rect& r) { return mosaic->ReadBlock(l, r); },
                    frame_rect, warp, level);
  return imaging::ResampleAffine(source.block, source.view_to_block, frame_rect.size());
}

}  // namespace fleetloc::tracking
