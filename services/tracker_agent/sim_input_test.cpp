// Live simulated vehicle: events in time order across stretches, the route and the odometry
// continuing without a jump where one stretch hands over to the next.
#include "tracker_agent/sim_input.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace fleetloc::tracker_agent {
namespace {

TEST(SimInput, DrivesOnAcrossStretchesWithoutJumps) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  mosaic::ImageRasterSource source(floor, {0.0, floor.rows * 0.0005, 0.0005});
  sim::SimOptions options;
  options.timing.frames = 10;  // short stretches: three handovers below
  const geometry::CameraModel camera = sim::DefaultSimCameraModel(320, 240, 0.0005);
  auto input = SimInput::Create(&source, camera, options, false);
  ASSERT_TRUE(input.ok()) << input.status().message();
  double last_t = -1;
  int frames = 0;
  geometry::Pose2 last_odom;
  double largest_odometry_step = 0, largest_truth_step = 0;
  geometry::Pose2 last_truth;
  while (frames < 40) {
    auto event = (*input)->Next();
    ASSERT_TRUE(event.ok()) << event.status().message();
    ASSERT_TRUE(event->has_value());
    const InputEvent& e = **event;
    EXPECT_GE(e.t, last_t);
    if (e.kind == InputEvent::Kind::kFrame) {
      ++frames;
      EXPECT_EQ(e.frame.size(), cv::Size(320, 240));
    } else {
      // The camera footprint moves at a constant 1.5 m/s (base_link swings in the turns).
      const geometry::Pose2 odom_camera = e.odom * camera.mount;
      const geometry::Pose2 truth = (*input)->TruthAt(e.t) * camera.mount;
      if (last_t >= 0) {
        largest_odometry_step =
            std::max(largest_odometry_step,
                     std::hypot(odom_camera.x - last_odom.x, odom_camera.y - last_odom.y));
        largest_truth_step = std::max(largest_truth_step,
                                      std::hypot(truth.x - last_truth.x, truth.y - last_truth.y));
      }
      last_odom = odom_camera;
      last_truth = truth;
    }
    last_t = e.t;
  }
  // 3000 px/s at 0.5 mm/px and 100 Hz odometry (± jitter): about 15 mm per sample for the
  // camera, in odometry too; a handover adds no jump.
  EXPECT_LT(largest_odometry_step, 0.02);
  EXPECT_LT(largest_truth_step, 0.02);
  EXPECT_GT(last_t, 7.0);  // 40 frames at 5 Hz
}

}  // namespace
}  // namespace fleetloc::tracker_agent
