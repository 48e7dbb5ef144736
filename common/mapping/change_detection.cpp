// Block-wise NCC between a frame and the predicted mosaic view.
#include "mapping/change_detection.h"

#include <opencv2/imgproc.hpp>

namespace fleetloc::mapping {

ChangeReport CompareWithMosaic(const cv::Mat& frame, const cv::Mat& view, const ChangeOptions& o) {
  CV_Assert(frame.size() == view.size() && frame.type() == CV_8UC1 && view.type() == CV_8UC1);
  ChangeReport report;
  for (int y = 0; y + o.block_px <= frame.rows; y += o.block_px) {
    for (int x = 0; x + o.block_px <= frame.cols; x += o.block_px) {
      const cv::Rect block(x, y, o.block_px, o.block_px);
      cv::Scalar frame_mean, frame_std, view_mean, view_std;
      cv::meanStdDev(frame(block), frame_mean, frame_std);
      if (cv::countNonZero(view(block)) < block.area() / 2) {
        // Floor the mosaic does not cover — if the camera sees textured floor there at all (not
        // darkness: 90 % of the block brighter than the dark level).
        const bool floor_seen = cv::countNonZero(frame(block) > o.dark_dn) >= block.area() * 9 / 10;
        if (floor_seen && frame_std[0] >= o.min_block_stddev) ++report.blocks, ++report.unmapped;
        continue;
      }
      cv::meanStdDev(view(block), view_mean, view_std);
      if (frame_std[0] < o.min_block_stddev && view_std[0] < o.min_block_stddev) continue;
      ++report.blocks;
      cv::Mat ncc;
      cv::matchTemplate(view(block), frame(block), ncc, cv::TM_CCOEFF_NORMED);
      if (ncc.at<float>(0, 0) < o.min_block_ncc) ++report.changed;
    }
  }
  return report;
}

}  // namespace fleetloc::mapping
