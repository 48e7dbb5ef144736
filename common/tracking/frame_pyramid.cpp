// The frame pyramid of one tracking cycle (see frame_pyramid.h).
#include "tracking/frame_pyramid.h"

#include <opencv2/imgproc.hpp>

namespace fleetloc::tracking {

cv::Mat FramePyramid::Level(int level) {
  while (static_cast<int>(levels_.size()) <= level) {
    const cv::Mat& last = levels_.back();
    cv::Mat next;
    cv::resize(last, next, {last.cols / 2, last.rows / 2}, 0, 0, cv::INTER_AREA);
    levels_.push_back(next);
  }
  return levels_[level];
}

}  // namespace fleetloc::tracking
