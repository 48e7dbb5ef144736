// A camera frame and its pyramid levels, shared by the steps of one tracking cycle so that each
// level is computed once (the templates' texture and coarse search, and the polish, read level 1).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace fleetloc::tracking {

class FramePyramid {
 public:
  explicit FramePyramid(const cv::Mat& frame) : levels_{frame} {}

  // Level `level` (0: the frame): each level is the last halved, area-averaged (cv::resize
  // INTER_AREA to half the size, rounded down), computed when first asked for; a header sharing
  // the pyramid's pixels.
  cv::Mat Level(int level);
  cv::Mat frame() const { return levels_.front(); }

 private:
  std::vector<cv::Mat> levels_;
};

}  // namespace fleetloc::tracking
