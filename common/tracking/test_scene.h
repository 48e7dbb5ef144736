// Test helper (tests only): a real floor photo as the mosaic and a 160×120 camera, with frames
// rendered at known poses straight from the formulas of docs/formats.md (cv::remap, independent of
// the tracker's own warp code). Needs FLEETLOC_SOURCE_DIR, which fleetloc_test() defines.
#pragma once

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "geometry/camera_model.h"
#include "geometry/geotransform.h"
#include "geometry/pose2.h"

namespace fleetloc::tracking {

struct TestScene {
  cv::Mat floor;  // tests/data/gravel.png, 512×512, 0.5 mm per pixel
  geometry::Geotransform geo{0.0, 512 * 0.0005, 0.0005};
  geometry::CameraModel camera;
  cv::RNG rng{7};

  TestScene() {
    floor = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
    camera.width_px = 160;
    camera.height_px = 120;
    camera.cx_px = 80;
    camera.cy_px = 60;
    camera.mount = {0.1, 0.0, 0.0};
  }

  // The frame base_link at `base` sees: pixel centre → ground → map → mosaic, per docs/formats.md;
  // bicubic, then gain and bias, a slight blur and Gaussian noise (sigma 2 grey levels, from the
  // scene's own seeded generator, so results do not depend on which tests ran before).
  cv::Mat Render(const geometry::Pose2& base, double gain, double bias) {
    cv::Mat map_x(camera.height_px, camera.width_px, CV_32F), map_y = map_x.clone();
    const geometry::Pose2 cam = base * camera.mount;
    for (int j = 0; j < camera.height_px; ++j) {
      for (int i = 0; i < camera.width_px; ++i) {
        const Eigen::Vector2d uv = geo.MapToPixel(cam * camera.PixelToGround({i + 0.5, j + 0.5}));
        map_x.at<float>(j, i) = static_cast<float>(uv.x() - 0.5);
        map_y.at<float>(j, i) = static_cast<float>(uv.y() - 0.5);
      }
    }
    cv::Mat frame, noise(camera.height_px, camera.width_px, CV_32F);
    cv::remap(floor, frame, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_CONSTANT);
    frame.convertTo(frame, CV_32F, gain, bias);
    cv::GaussianBlur(frame, frame, {0, 0}, 0.7);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 2.0);
    frame += noise;
    frame.convertTo(frame, CV_8U);
    return frame;
  }
};

}  // namespace fleetloc::tracking
