// GstCamera on real GStreamer pipelines: a live videotestsrc's buffer timestamps (PTS on the
// pipeline clock) land on the host clock a frame period apart; a camera's own clock (device
// timestamps an hour off) lands on the host clock at its arrival less the smallest delay, after
// the settling frames; frame_rate stamps the run's grid;
// a UDP source that stops sending stalls the pipeline without blocking Grab and its frames come
// back when it resumes; the end of the stream, unsupported formats and bad pipelines are errors
// or counted drops, never crashes.
#include "camera_io/gst_camera.h"

#include <gtest/gtest.h>

#include "camera_io/udp_test_frames.h"

namespace fleetloc::camera_io {
namespace {

std::unique_ptr<GstCamera> OpenOrDie(const GstOptions& options) {
  auto camera = GstCamera::Open(options);
  EXPECT_TRUE(camera.ok()) << camera.status().message();
  return camera.ok() ? std::move(camera).value() : nullptr;
}

// The next frame, waiting up to 5 s (the pipeline delivers within a frame period).
std::optional<CapturedFrame> Next(GstCamera& camera) {
  auto frame = camera.Grab(5.0);
  EXPECT_TRUE(frame.ok()) << frame.status().message();
  return frame.ok() ? *frame : std::nullopt;
}

TEST(GstCamera, ALiveSourcesBufferTimestampsArePtsOnTheHostClock) {
  const double before_open = HostNow();
  auto camera =
      OpenOrDie({"videotestsrc is-live=true num-buffers=5 ! "
                 "video/x-raw,format=GRAY8,width=64,height=48,framerate=10/1 ! appsink",
                 "buffer"});
  ASSERT_TRUE(camera);
  std::vector<double> t;
  for (int i = 0; i < 5; ++i) {
    std::optional<CapturedFrame> frame = Next(*camera);
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->image.size(), cv::Size(64, 48));
    EXPECT_EQ(frame->image.type(), CV_8UC1);
    EXPECT_LE(frame->t, frame->arrival_t);  // captured, then delivered
    EXPECT_GE(frame->t, before_open);       // not before the pipeline existed
    t.push_back(frame->t);
  }
  // The PTS are a frame period apart whatever the delivery did (the mapping reads both clocks at
  // each frame: a few microseconds of its own).
  for (size_t i = 1; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], 0.1, 50e-6) << i;
  auto end = camera->Grab(5.0);
  ASSERT_FALSE(end.ok());
  EXPECT_NE(end.status().message().find("end of stream"), std::string::npos);
  EXPECT_EQ(camera->stats().frames, 5);
}

TEST(GstCamera, DeviceTimestampsAreMappedToTheHostClockBySmallestDelay) {
  // PTS an hour ahead of the pipeline's running time: a clock of the camera's own.
  auto camera =
      OpenOrDie({"videotestsrc is-live=true num-buffers=8 timestamp-offset=3600000000000 ! "
                 "video/x-raw,format=GRAY8,width=64,height=48,framerate=20/1 ! "
                 "appsink sync=false",
                 "device"});
  ASSERT_TRUE(camera);
  std::vector<double> t;
  for (int grabs = 0; grabs < 8; ++grabs) {
    auto frame = camera->Grab(5.0);
    ASSERT_TRUE(frame.ok()) << frame.status().message();
    if (!frame->has_value()) continue;  // a settling frame
    EXPECT_LE((*frame)->t, (*frame)->arrival_t);
    EXPECT_LT((*frame)->arrival_t - (*frame)->t, 0.05);  // within the delivery delay, not an hour
    t.push_back((*frame)->t);
  }
  EXPECT_EQ(camera->stats().clock_settling, kClockSettleFrames - 1);
  ASSERT_EQ(t.size(), 8u - (kClockSettleFrames - 1));
  // A frame period apart, up to how much the smallest delay still moved.
  for (size_t i = 1; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], 0.05, 0.005) << i;
}

TEST(GstCamera, FrameRateTimestampsPutFrameNAtEpochPlusNOverTheFrameRate) {
  auto camera =
      OpenOrDie({"videotestsrc num-buffers=3 ! "
                 "video/x-raw,format=BGR,width=32,height=24,framerate=4/1 ! appsink sync=false",
                 "frame_rate", 1000.0});
  ASSERT_TRUE(camera);
  for (int i = 0; i < 3; ++i) {
    std::optional<CapturedFrame> frame = Next(*camera);
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->t, 1000.0 + 0.25 * i);
    EXPECT_EQ(frame->image.type(), CV_8UC1);  // BGR turned gray
  }
}

TEST(GstCamera, PipelineClockTimesMapToTheHostClockByTheirAge) {
  EXPECT_DOUBLE_EQ(PipelineClockToHost(4'000'000'000ULL, 4'250'000'000ULL, 100.0), 99.75);
  // A buffer stamped after the clock reading (a pipeline running ahead): never after now.
  EXPECT_DOUBLE_EQ(PipelineClockToHost(5'000'000'000ULL, 4'000'000'000ULL, 100.0), 100.0);
}

TEST(GstCamera, AStalledUdpSourceTimesOutAndItsFramesReturnWhenItResumes) {
  const int port = testing::UdpFrameSender::FreePort();
  ASSERT_GT(port, 0);
  auto camera = OpenOrDie({testing::UdpGrayPipeline(port, 16, 8), "buffer"});
  ASSERT_TRUE(camera);
  testing::UdpFrameSender sender;
  const cv::Mat gray(8, 16, CV_8UC1, cv::Scalar(42));
  // Grab keeps returning while nothing comes: the caller sees the stall.
  auto silent = camera->Grab(0.1);
  ASSERT_TRUE(silent.ok()) << silent.status().message();
  EXPECT_FALSE(silent->has_value());
  std::optional<CapturedFrame> frame;
  for (int i = 0; i < 50 && !frame; ++i) {  // the first datagrams may precede the socket
    ASSERT_TRUE(sender.Send(gray, port));
    auto grabbed = camera->Grab(0.1);
    ASSERT_TRUE(grabbed.ok());
    frame = *grabbed;
  }
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->image.at<uint8_t>(3, 5), 42);
  EXPECT_LE(frame->t, frame->arrival_t);
}

TEST(GstCamera, AnUnsupportedFormatIsADroppedFrame) {
  auto camera =
      OpenOrDie({"videotestsrc num-buffers=1 ! "
                 "video/x-raw,format=I420,width=32,height=24 ! appsink",
                 "buffer"});
  ASSERT_TRUE(camera);
  auto frame = camera->Grab(5.0);
  ASSERT_TRUE(frame.ok()) << frame.status().message();
  EXPECT_FALSE(frame->has_value());
  EXPECT_EQ(camera->stats().dropped, 1);
  EXPECT_NE(camera->stats().last_drop.find("I420"), std::string::npos) << camera->stats().last_drop;
}

TEST(GstCamera, BadPipelinesAreNamedErrors) {
  auto unknown = GstCamera::Open({"nosuchelement ! appsink", "buffer"});
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.status().message().find("nosuchelement"), std::string::npos)
      << unknown.status().message();
  auto no_appsink = GstCamera::Open({"videotestsrc ! fakesink name=appsink", "buffer"});
  ASSERT_FALSE(no_appsink.ok());
  EXPECT_NE(no_appsink.status().message().find("has no appsink"), std::string::npos);
  EXPECT_FALSE(GstCamera::Open({"videotestsrc ! appsink", "pts"}).ok());
}

}  // namespace
}  // namespace fleetloc::camera_io
