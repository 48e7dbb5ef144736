// Block-wise NCC between a frame and the predicted mosaic view.
#include "mapping/change_detection.h"

#include <opencv2/imgproc.hpp>

namespace fleetloc::mapping {
namespace {

BlockComparison CompareBlock(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& block,
                             const ChangeOptions& o) {
  BlockComparison c;
  c.rect = block;
  cv::Scalar mean, stddev;
  cv::meanStdDev(frame(block), mean, stddev);
  c.frame_stddev = stddev[0];
  c.floor_seen = cv::countNonZero(frame(block) > o.dark_dn) >= block.area() * 9 / 10;
  c.mapped = cv::countNonZero(view(block)) >= block.area() / 2;
  if (!c.mapped) return c;
  cv::meanStdDev(view(block), mean, stddev);
  c.view_stddev = stddev[0];
  // A flat side has no correlation to speak of (matchTemplate's answer there is undefined).
  if (c.frame_stddev < 1e-3 || c.view_stddev < 1e-3) return c;
  cv::Mat ncc;
  cv::matchTemplate(view(block), frame(block), ncc, cv::TM_CCOEFF_NORMED);
  c.ncc = ncc.at<float>(0, 0);
  return c;
}

}  // namespace

std::vector<BlockComparison> CompareBlocks(const cv::Mat& frame, const cv::Mat& view,
                                           const ChangeOptions& o) {
  CV_Assert(frame.size() == view.size() && frame.type() == CV_8UC1 && view.type() == CV_8UC1);
  std::vector<BlockComparison> blocks;
  for (int y = 0; y + o.block_px <= frame.rows; y += o.block_px) {
    for (int x = 0; x + o.block_px <= frame.cols; x += o.block_px) {
      blocks.push_back(CompareBlock(frame, view, {x, y, o.block_px, o.block_px}, o));
    }
  }
  return blocks;
}

ChangeReport CompareWithMosaic(const cv::Mat& frame, const cv::Mat& view, const ChangeOptions& o) {
  ChangeReport report;
  for (const BlockComparison& b : CompareBlocks(frame, view, o)) {
    if (!b.mapped) {
      // Floor the mosaic does not cover — if the camera sees textured floor there at all.
      if (b.floor_seen && b.frame_stddev >= o.min_block_stddev) {
        ++report.blocks;
        ++report.unmapped;
      }
      continue;
    }
    if (!b.textured(o.min_block_stddev)) continue;
    ++report.blocks;
    if (b.ncc < o.min_block_ncc) ++report.changed;
  }
  return report;
}

}  // namespace fleetloc::mapping
