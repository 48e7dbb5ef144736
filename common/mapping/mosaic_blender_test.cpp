// Tests for blending: frames of a real photo (tests/data/gravel.png via tracking/test_scene.h)
// rendered at known poses with different gains are blended back at those poses; the result matches
// the photo (seen through the same lens blur), unmapped pixels stay 0, and the canvas covers every
// footprint on the resolution's grid.
#include "mapping/mosaic_blender.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "geometry/footprint.h"
#include "tracking/test_scene.h"

namespace fleetloc::mapping {
namespace {

using geometry::Pose2;

struct Frames {
  std::vector<cv::Mat> images;
  std::vector<Pose2> cameras;  // camera_ground in map
};

// 12 frames of 160×120 along a diagonal, turning, with gains 0.8 … 1.25 (the first at 1).
Frames Render(tracking::TestScene& scene) {
  Frames frames;
  for (int k = 0; k < 12; ++k) {
    const Pose2 camera{0.08 + 0.008 * k, 0.09 + 0.006 * k, 0.2 + 0.05 * k};
    frames.cameras.push_back(camera);
    const double gain = k == 0 ? 1.0 : 0.8 + 0.04 * k;
    frames.images.push_back(
        scene.Render(camera * scene.camera.mount.Inverse(), gain, 4.0 * (k % 3)));
  }
  return frames;
}

// Mean absolute difference (grey levels) between the blended canvas and the blurred photo over
// canvas pixels that at least three frames cover well (weight of the centre region).
double MeanError(const MosaicBlender& blender, const cv::Mat& reference, const cv::Mat& coverage) {
  const Canvas& c = blender.canvas();
  const int du = static_cast<int>(std::lround(c.geo.origin_x / c.geo.resolution));
  const int dv = static_cast<int>(std::lround((0.256 - c.geo.origin_y) / c.geo.resolution));
  std::vector<std::uint8_t> row(c.width_px);
  double sum = 0;
  int n = 0;
  for (int v = 0; v < c.height_px; ++v) {
    blender.Row(v, row);
    for (int u = 0; u < c.width_px; ++u) {
      if (coverage.at<std::uint8_t>(v, u) < 3) continue;
      sum += std::abs(row[u] - reference.at<float>(v + dv, u + du));
      ++n;
    }
  }
  EXPECT_GT(n, 5000);
  return sum / n;
}

// How many frames' inner halves cover each canvas pixel.
cv::Mat Coverage(const Canvas& canvas, const Frames& frames, const geometry::CameraModel& camera) {
  cv::Mat coverage = cv::Mat::zeros(canvas.height_px, canvas.width_px, CV_8U);
  geometry::CameraModel inner = camera;
  inner.width_px /= 2;
  inner.height_px /= 2;
  inner.cx_px /= 2;
  inner.cy_px /= 2;
  for (const Pose2& pose : frames.cameras) {
    const geometry::ConvexPolygon footprint =
        geometry::PlaceFootprint(geometry::FootprintInGround(inner), pose);
    for (int v = 0; v < canvas.height_px; ++v) {
      for (int u = 0; u < canvas.width_px; ++u) {
        if (geometry::Contains(footprint, canvas.geo.PixelToMap({u + 0.5, v + 0.5}))) {
          ++coverage.at<std::uint8_t>(v, u);
        }
      }
    }
  }
  return coverage;
}

TEST(MosaicBlender, BlendingFramesAtTheirPosesRebuildsThePhoto) {
  tracking::TestScene scene;
  const Frames frames = Render(scene);
  const Result<Canvas> canvas = CanvasFor(frames.cameras, scene.camera, BlendOptions{});
  ASSERT_TRUE(canvas.ok()) << canvas.status().message();
  cv::Mat reference;  // the photo as the camera sees it (lens blur), in floats
  scene.floor.convertTo(reference, CV_32F);
  cv::GaussianBlur(reference, reference, {0, 0}, 0.7);
  const cv::Mat coverage = Coverage(*canvas, frames, scene.camera);

  BlendOptions no_gain;
  no_gain.normalize_gain = false;
  MosaicBlender plain(*canvas, scene.camera, no_gain), normalized(*canvas, scene.camera, {});
  std::vector<double> gains;
  for (size_t k = 0; k < frames.images.size(); ++k) {
    plain.Add(frames.images[k], frames.cameras[k]);
    gains.push_back(normalized.Add(frames.images[k], frames.cameras[k]));
  }
  EXPECT_DOUBLE_EQ(gains[0], 1.0);                        // nothing accumulated yet
  EXPECT_NEAR(gains[11], 1.0 / (0.8 + 0.04 * 11), 0.03);  // undoes the frame's gain
  // Noise is σ 2 per frame; after gain normalization the mosaic is the photo to ~1.5 grey levels
  // (measured 1.45; without normalization 12.6).
  const double normalized_error = MeanError(normalized, reference, coverage);
  EXPECT_LT(normalized_error, 2.0);
  EXPECT_GT(MeanError(plain, reference, coverage), 2.0 * normalized_error);
}

TEST(MosaicBlender, UnmappedPixelsAreZeroAndMappedOnesNever) {
  tracking::TestScene scene;
  const Pose2 camera{0.1, 0.1, M_PI / 4};  // one frame turned 45°: the canvas corners stay empty
  const Result<Canvas> canvas = CanvasFor({camera}, scene.camera, BlendOptions{});
  ASSERT_TRUE(canvas.ok());
  MosaicBlender blender(*canvas, scene.camera, {});
  blender.Add(cv::Mat(scene.camera.height_px, scene.camera.width_px, CV_8U, cv::Scalar(0)), camera);
  std::vector<std::uint8_t> row(canvas->width_px);
  blender.Row(0, row);
  EXPECT_EQ(row.front(), 0);
  blender.Row(canvas->height_px / 2, row);
  EXPECT_EQ(row[canvas->width_px / 2], 1);  // a black floor is stored as 1: 0 means unmapped
}

TEST(MosaicBlender, CanvasCoversEveryFootprintOnTheResolutionGrid) {
  tracking::TestScene scene;
  const std::vector<Pose2> cameras{{0.1003, 0.2001, 0.3}, {0.1502, 0.1707, -1.0}};
  const Result<Canvas> canvas = CanvasFor(cameras, scene.camera, BlendOptions{});
  ASSERT_TRUE(canvas.ok());
  const double res = scene.camera.resolution_m;
  EXPECT_NEAR(canvas->geo.origin_x / res, std::round(canvas->geo.origin_x / res), 1e-6);
  EXPECT_NEAR(canvas->geo.origin_y / res, std::round(canvas->geo.origin_y / res), 1e-6);
  for (const Pose2& pose : cameras) {
    for (const Eigen::Vector2d& corner :
         geometry::PlaceFootprint(geometry::FootprintInGround(scene.camera), pose)) {
      const Eigen::Vector2d px = canvas->geo.MapToPixel(corner);
      EXPECT_GE(px.x(), 0.0);
      EXPECT_GE(px.y(), 0.0);
      EXPECT_LE(px.x(), canvas->width_px);
      EXPECT_LE(px.y(), canvas->height_px);
    }
  }
  BlendOptions tiny;
  tiny.max_canvas_mb = 0.01;
  const Result<Canvas> refused = CanvasFor(cameras, scene.camera, tiny);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("blending canvas"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::mapping
