// RectifierFor: a top-view camera gets none; a raw camera whose lens is ideal and whose ground
// homography is the top view's own pixel → floor mapping is rectified into the same image.
#include "rectification/camera_rectifier.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace fleetloc::rectification {
namespace {

geometry::CameraModel SmallTopView() {
  geometry::CameraModel model;
  model.width_px = 64;
  model.height_px = 48;
  model.cx_px = 32;
  model.cy_px = 24;
  return model;
}

TEST(CameraRectifier, TopViewCameraNeedsNoRectifier) {
  EXPECT_FALSE(RectifierFor(run_io::CameraFile{SmallTopView(), std::nullopt}).has_value());
}

TEST(CameraRectifier, IdealRawCameraOverTheTopViewRectifiesToTheSameImage) {
  const geometry::CameraModel model = SmallTopView();
  const double res = model.resolution_m;
  run_io::RawCamera raw;
  raw.K = {500, 0, model.cx_px, 0, 500, model.cy_px, 0, 0, 1};
  raw.dist = {0, 0, 0, 0, 0};
  // (u, v) → (a, b) = (-(v - cy)·res, -(u - cx)·res): the top view's own PixelToGround.
  raw.H_ground = {0, -res, res * model.cy_px, -res, 0, res * model.cx_px, 0, 0, 1};
  const std::optional<calibration::Rectifier> rectifier = RectifierFor({model, raw});
  ASSERT_TRUE(rectifier.has_value());

  cv::Mat frame(model.height_px, model.width_px, CV_8UC1);
  cv::randu(frame, 0, 256);
  const cv::Mat rectified = rectifier->Rectify(frame);
  ASSERT_EQ(rectified.size(), frame.size());
  const cv::Rect inner(1, 1, model.width_px - 2, model.height_px - 2);
  EXPECT_LE(cv::norm(rectified(inner), frame(inner), cv::NORM_INF), 1.0);
}

}  // namespace
}  // namespace fleetloc::rectification
