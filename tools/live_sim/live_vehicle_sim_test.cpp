// The simulated live vehicle's frame timing: which planned frame a camera firing on the frame
// grid shows, and stamps, at a given moment — never one due after that moment.
#include "live_sim/live_vehicle_sim.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

namespace fleetloc::live_sim {
namespace {

std::unique_ptr<PlannedDrive> FiveFrameDrive() {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  auto drive = PlannedDrive::Create(floor, 0.0005, 5, 10.0, 1000.0, 2.0, 1000.0, 20);
  EXPECT_TRUE(drive.ok()) << drive.status().message();
  return drive.ok() ? std::move(drive).value() : nullptr;
}

TEST(PlannedDrive, AFrameFilledLateShowsTheFrameDueBeforeItNeverTheNextOne) {
  const std::unique_ptr<PlannedDrive> drive = FiveFrameDrive();
  ASSERT_NE(drive, nullptr);
  const double first = drive->first_frame_t();
  EXPECT_DOUBLE_EQ(first, 1002.0);
  ASSERT_EQ(drive->frame_count(), 5);
  // On time (a microsecond after the grid time), and 57 ms late: the same frame, stamped at its
  // grid time, before the fill. The nearest frame (FrameAt) would be the next one, due 43 ms later.
  EXPECT_EQ(drive->FrameCapturedBy(first + 0.200001), 2);
  EXPECT_EQ(drive->FrameCapturedBy(first + 0.257), 2);
  EXPECT_EQ(drive->FrameAt(first + 0.257), 3);
  EXPECT_LE(drive->frame_t(*drive->FrameCapturedBy(first + 0.257)), first + 0.257);
  // A grid time a rounding error early still counts as that frame.
  EXPECT_EQ(drive->FrameCapturedBy(first + 0.3 - 1e-9), 3);
  // Before the drive, and a period after its last frame: no planned frame.
  EXPECT_FALSE(drive->FrameCapturedBy(first - 0.01).has_value());
  EXPECT_EQ(drive->FrameCapturedBy(first + 0.45), 4);
  EXPECT_FALSE(drive->FrameCapturedBy(first + 0.5).has_value());
}

}  // namespace
}  // namespace fleetloc::live_sim
