// PlannedDrive: which planned frame the fake camera shows at a fill time. A fill that comes late
// (the fake camera's thread stalled) shows the newest frame already captured, never one captured
// after the fill: such a frame would arrive before its own capture time (a negative transfer
// delay), which the agent's minimum-delay clock mapping takes as its offset, moving the stamps of
// the frames after it early (and the next fill showed the same frame again).
#include "live_sim/live_vehicle_sim.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace fleetloc::live_sim {
namespace {

TEST(PlannedDriveTest, AFillShowsTheNewestFrameCapturedByThenNeverALaterOne) {
  cv::Mat floor(1024, 1024, CV_8UC1);
  cv::randu(floor, 0, 255);
  auto drive = PlannedDrive::Create(floor, 0.0005, 5, 10.0, 1000.0, 1.0, 200.0, 20);
  ASSERT_TRUE(drive.ok()) << drive.status().message();
  const PlannedDrive& d = **drive;
  const double t2 = d.frame_t(2);
  EXPECT_EQ(d.FrameCapturedBy(t2), 2);           // a fill on the frame's own instant
  EXPECT_EQ(d.FrameCapturedBy(t2 + 0.002), 2);   // a fill just after it
  EXPECT_EQ(d.FrameCapturedBy(t2 + 0.06), 2);    // late past half a period: still frame 2
  EXPECT_EQ(d.FrameCapturedBy(t2 + 0.099), 2);
  EXPECT_EQ(d.FrameCapturedBy(t2 - 0.001), 1);   // frame 2 is not captured yet
  EXPECT_EQ(d.FrameCapturedBy(d.first_frame_t() - 5.0), 0);  // before the drive: the first
  EXPECT_EQ(d.FrameCapturedBy(d.last_frame_t() + 5.0), d.frame_count() - 1);
  for (double t = d.first_frame_t(); t < d.last_frame_t(); t += 0.013)
    EXPECT_LE(d.frame_t(d.FrameCapturedBy(t)), t + 1e-6) << t;
  EXPECT_EQ(d.FrameAt(t2 + 0.06), 3);  // the nearest frame, which the fill used to show
}

}  // namespace
}  // namespace fleetloc::live_sim
