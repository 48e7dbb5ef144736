// LiveInput: a scripted camera and ROS 2 odometry over DDS (a private domain); each kind of bad
// input becomes its named issue and clears when the source is good again; frames of the wrong
// size and odometry that is not finite or goes back in time are dropped; odometry that restarts
// with an older clock becomes a new timeline; a real GStreamer pipeline that stalls is reopened and
// recovers when its source returns.
#include "tracker_agent/live_input.h"

#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <thread>

#include "base/eventually.h"
#include "camera_io/udp_test_frames.h"
#include "transport/ros_messages.h"

namespace fleetloc::tracker_agent {
namespace {

using testing::Eventually;

// What the scripted camera does when grabbed.
struct Script {
  std::atomic<bool> present{true};   // the opener finds it
  std::atomic<bool> failing{false};  // Grab reports the device gone
  std::atomic<bool> silent{false};   // Grab times out
  std::atomic<int> width{64};
  std::atomic<bool> repeat_time{false};  // frames carry the previous frame's time again
  std::atomic<int> opens{0};
  std::atomic<double> close_s{0.0};  // closing takes this long (a GigE Vision camera that is gone)
};

class ScriptedCamera : public camera_io::CameraSource {
 public:
  explicit ScriptedCamera(Script* script) : script_(script) {}
  ~ScriptedCamera() override {
    std::this_thread::sleep_for(std::chrono::duration<double>(script_->close_s.load()));
  }
  Result<std::optional<camera_io::CapturedFrame>> Grab(double /*timeout_s*/) override {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (script_->failing) return Internal("scripted: device gone");
    if (script_->silent) return std::optional<camera_io::CapturedFrame>();
    camera_io::CapturedFrame frame;
    frame.image = cv::Mat(48, script_->width, CV_8UC1, cv::Scalar(7));
    frame.t = frame.arrival_t = camera_io::HostNow();
    if (script_->repeat_time && last_t_ > 0) frame.t = last_t_;
    last_t_ = frame.t;
    return std::optional<camera_io::CapturedFrame>(frame);
  }
  camera_io::CameraStats stats() const override { return {}; }
  std::string Describe() const override { return "scripted camera"; }

 private:
  Script* script_;
  double last_t_ = 0.0;
};

class LiveInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_.source = "aravis";
    config_.domain_id = 123;
    config_.ros.enabled = true;
    config_.live.camera_stall_s = 0.3;
    config_.live.camera_reopen_s = 0.6;
    config_.live.odometry_stale_s = 0.3;
    config_.live.issue_hold_s = 0.8;
    camera_.model.width_px = 64;
    camera_.model.height_px = 48;
    LiveInput::CameraOpener opener = Opener();
    auto input = LiveInput::Create(config_, camera_, std::move(opener));
    ASSERT_TRUE(input.ok()) << input.status().message();
    input_ = std::move(input).value();
    auto p = transport::Participant::Create(config_.domain_id);
    ASSERT_TRUE(p.ok());
    participant_ = std::make_unique<transport::Participant>(std::move(p).value());
    auto topic = transport::Topic<nav_msgs_msg_dds__Odometry_>::Create(*participant_, "rt/odom");
    topic_ =
        std::make_unique<transport::Topic<nav_msgs_msg_dds__Odometry_>>(std::move(topic).value());
    auto writer = transport::Writer<nav_msgs_msg_dds__Odometry_>::Create(participant_->get(),
                                                                         *topic_, RosDefaultQos());
    writer_ =
        std::make_unique<transport::Writer<nav_msgs_msg_dds__Odometry_>>(std::move(writer).value());
    ASSERT_TRUE(Eventually([&] { return writer_->MatchedReaders() > 0; }, 10));
  }
  // The scripted camera (script_ says what it does).
  virtual LiveInput::CameraOpener Opener() {
    return [this]() -> Result<std::unique_ptr<camera_io::CameraSource>> {
      if (!script_.present) return NotFound("scripted: no camera");
      ++script_.opens;
      return std::unique_ptr<camera_io::CameraSource>(new ScriptedCamera(&script_));
    };
  }
  void SendOdometry(double t, double x) {
    nav_msgs_msg_dds__Odometry_ m{};
    m.header.stamp = transport::ToRosTime(t);
    m.pose.pose.position = {x, 0.0, 0.0};
    m.pose.pose.orientation = transport::QuaternionOfYaw(0.0);
    ASSERT_TRUE(writer_->Write(m).ok());
  }
  // Pumps Next() for `seconds`; returns the events by kind.
  std::vector<InputEvent> Pump(double seconds) {
    std::vector<InputEvent> events;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      auto e = input_->Next();
      EXPECT_TRUE(e.ok());
      if (e.ok() && e->has_value() && (*e)->kind != InputEvent::Kind::kIdle)
        events.push_back(std::move(**e));
    }
    return events;
  }
  bool HasIssue(const std::string& name) const {
    for (const InputIssue& issue : input_->Issues()) {
      if (issue.name == name) return true;
    }
    return false;
  }
  static int Count(const std::vector<InputEvent>& events, InputEvent::Kind kind) {
    return static_cast<int>(std::count_if(events.begin(), events.end(),
                                          [&](const InputEvent& e) { return e.kind == kind; }));
  }

  AgentConfig config_;
  run_io::CameraFile camera_;
  Script script_;
  std::unique_ptr<LiveInput> input_;
  std::unique_ptr<transport::Participant> participant_;
  std::unique_ptr<transport::Topic<nav_msgs_msg_dds__Odometry_>> topic_;
  std::unique_ptr<transport::Writer<nav_msgs_msg_dds__Odometry_>> writer_;
};

TEST_F(LiveInputTest, FramesOfTheWrongSizeAreDroppedAndNamedUntilTheSizeIsRight) {
  EXPECT_GT(Count(Pump(0.3), InputEvent::Kind::kFrame), 5);
  EXPECT_EQ(input_->DroppedFrames(), 0);
  script_.width = 80;
  EXPECT_EQ(Count(Pump(0.3), InputEvent::Kind::kFrame), 0);
  EXPECT_GT(input_->DroppedFrames(), 5);
  ASSERT_TRUE(HasIssue("camera_wrong_format"));
  for (const InputIssue& issue : input_->Issues()) {
    if (issue.name == "camera_wrong_format") {
      EXPECT_EQ(issue.message, "frame 80x48, camera.json expects 64x48");
    }
  }
  script_.width = 64;
  EXPECT_GT(Count(Pump(0.3), InputEvent::Kind::kFrame), 5);
  Pump(0.8);  // the hold
  EXPECT_FALSE(HasIssue("camera_wrong_format"));
}

// A camera whose frame time does not advance (a repeated frame, a device clock mapped back): the
// frames are dropped before the tracker, counted, and named camera_back_in_time (not a wrong
// format: the image is fine) until the hold after time advances again.
TEST_F(LiveInputTest, FramesWhoseTimeDoesNotAdvanceAreDroppedAndNamedBackInTime) {
  std::vector<InputEvent> events = Pump(0.3);
  ASSERT_GT(Count(events, InputEvent::Kind::kFrame), 0);
  EXPECT_FALSE(HasIssue("camera_back_in_time"));
  script_.repeat_time = true;
  const long long dropped_before = input_->DroppedFrames();
  events = Pump(0.3);
  EXPECT_LE(Count(events, InputEvent::Kind::kFrame), 1);  // at most one grabbed before the switch
  EXPECT_GE(input_->DroppedFrames() - dropped_before, 5);
  EXPECT_TRUE(HasIssue("camera_back_in_time"));
  EXPECT_FALSE(HasIssue("camera_wrong_format"));
  script_.repeat_time = false;
  events = Pump(0.3);
  EXPECT_GT(Count(events, InputEvent::Kind::kFrame), 0);
  Pump(config_.live.issue_hold_s);
  EXPECT_FALSE(HasIssue("camera_back_in_time"));  // the hold has passed
}

TEST_F(LiveInputTest, ACameraThatGoesAwayIsUnavailableThenReopened) {
  Pump(0.2);
  EXPECT_FALSE(HasIssue("camera_unavailable"));
  script_.present = false;
  script_.failing = true;
  Pump(0.3);
  EXPECT_TRUE(HasIssue("camera_unavailable"));
  script_.present = true;
  script_.failing = false;
  Pump(1.2);  // the opener is retried every second
  EXPECT_FALSE(HasIssue("camera_unavailable"));
  EXPECT_FALSE(HasIssue("camera_stalled"));
  EXPECT_GE(script_.opens, 2);
  EXPECT_GT(Count(Pump(0.2), InputEvent::Kind::kFrame), 3);
}

// Closing a camera that is gone can take seconds (Aravis waits out its control channel's
// timeouts): the camera is named unavailable at once and reopened without waiting for the close.
TEST_F(LiveInputTest, ACameraWhoseCloseHangsIsNamedAndReopenedWithoutWaitingForTheClose) {
  Pump(0.2);
  script_.close_s = 3.0;
  script_.present = false;
  script_.failing = true;
  Pump(0.3);
  EXPECT_TRUE(HasIssue("camera_unavailable"));
  script_.present = true;
  script_.failing = false;
  script_.close_s = 0.0;
  Pump(1.2);  // the reopening, 1.2 s into a 3-s close
  EXPECT_GE(script_.opens, 2);
  EXPECT_GT(Count(Pump(0.2), InputEvent::Kind::kFrame), 3);
  EXPECT_FALSE(HasIssue("camera_unavailable"));
}

TEST_F(LiveInputTest, ASilentCameraIsStalledThenReopened) {
  Pump(0.2);
  script_.silent = true;
  Pump(0.5);
  EXPECT_TRUE(HasIssue("camera_stalled"));
  EXPECT_EQ(script_.opens, 1);
  Pump(0.4);  // past camera_reopen_s: closed and opened again
  EXPECT_EQ(script_.opens, 2);
  script_.silent = false;
  Pump(0.2);
  EXPECT_FALSE(HasIssue("camera_stalled"));
}

// The same input over a real GStreamer pipeline: udpsrc, fed by the test, which stops sending
// (the pipeline stalls) and resumes.
class LiveInputGstreamerTest : public LiveInputTest {
 protected:
  LiveInput::CameraOpener Opener() override {
    port_ = camera_io::testing::UdpFrameSender::FreePort();
    config_.source = "gstreamer";
    config_.live.gstreamer = {camera_io::testing::UdpGrayPipeline(port_, 64, 48), "buffer"};
    return [this, open = LiveInput::OpenerFor(config_)] {
      ++script_.opens;
      return open();
    };
  }
  // Pump() while sending a frame every 20 ms.
  std::vector<InputEvent> PumpSending(double seconds) {
    std::vector<InputEvent> events;
    const cv::Mat frame(48, 64, CV_8UC1, cv::Scalar(9));
    for (double sent = 0; sent < seconds; sent += 0.02) {
      EXPECT_TRUE(sender_.Send(frame, port_));
      for (InputEvent& e : Pump(0.02)) events.push_back(std::move(e));
    }
    return events;
  }
  int port_ = 0;
  camera_io::testing::UdpFrameSender sender_;
};

TEST_F(LiveInputGstreamerTest, AStalledPipelineIsNamedReopenedAndRecoversWhenItsSourceReturns) {
  ASSERT_GT(port_, 0);
  EXPECT_GT(Count(PumpSending(0.5), InputEvent::Kind::kFrame), 5);
  EXPECT_FALSE(HasIssue("camera_stalled"));
  EXPECT_EQ(script_.opens, 1);
  Pump(0.45);  // silent past camera_stall_s
  EXPECT_TRUE(HasIssue("camera_stalled") || HasIssue("camera_unavailable"));
  Pump(0.6);  // past camera_reopen_s: the pipeline was closed and started again
  EXPECT_GE(script_.opens, 2);
  const std::vector<InputEvent> back = PumpSending(0.6);
  EXPECT_GT(Count(back, InputEvent::Kind::kFrame), 5);
  double last = 0;
  for (const InputEvent& e : back) {
    if (e.kind != InputEvent::Kind::kFrame) continue;
    EXPECT_GT(e.t, last);  // the new pipeline's buffer times, on the host clock, in order
    last = e.t;
  }
  EXPECT_FALSE(HasIssue("camera_stalled"));
  EXPECT_FALSE(HasIssue("camera_unavailable"));
}

TEST_F(LiveInputTest, BadOdometryIsDroppedAndNamedAndStaleOdometryIsNoticed) {
  const double t0 = 500.0;
  for (int i = 0; i < 10; ++i) SendOdometry(t0 + 0.01 * i, 0.1 * i);
  std::vector<InputEvent> events = Pump(0.1);
  EXPECT_EQ(Count(events, InputEvent::Kind::kOdometry), 10);
  EXPECT_FALSE(HasIssue("odometry_stale"));
  SendOdometry(t0 + 0.05, 9.0);                                      // back in time
  SendOdometry(t0 + 0.2, std::numeric_limits<double>::quiet_NaN());  // NaN
  SendOdometry(t0 + 0.21, 2.1);
  events = Pump(0.1);
  ASSERT_EQ(Count(events, InputEvent::Kind::kOdometry), 1);
  for (const InputEvent& e : events) {
    if (e.kind == InputEvent::Kind::kOdometry) {
      EXPECT_EQ(e.odom.x, 2.1);
    }
  }
  EXPECT_TRUE(HasIssue("odometry_back_in_time"));
  EXPECT_TRUE(HasIssue("odometry_not_finite"));
  Pump(0.3);
  EXPECT_TRUE(HasIssue("odometry_stale"));  // nothing since
  for (int i = 0; i < 9; ++i) {             // flowing again
    SendOdometry(t0 + 1.0 + 0.1 * i, 3.0);
    Pump(0.1);
  }
  EXPECT_FALSE(HasIssue("odometry_stale"));
  EXPECT_FALSE(HasIssue("odometry_back_in_time"));  // the hold has passed
  EXPECT_FALSE(HasIssue("odometry_not_finite"));
}

TEST_F(LiveInputTest, OdometryThatRestartsWithAnOlderClockBecomesANewTimeline) {
  for (int i = 0; i < 5; ++i) SendOdometry(100.0 + 0.01 * i, 0.0);
  Pump(0.1);
  std::vector<InputEvent> events;
  for (int i = 0; i < 40; ++i) {  // a restarted base controller: its clock starts at 0 again
    SendOdometry(0.01 * i, 0.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    for (InputEvent& e : Pump(0.005)) events.push_back(std::move(e));
  }
  for (InputEvent& e : Pump(0.05)) events.push_back(std::move(e));
  ASSERT_EQ(Count(events, InputEvent::Kind::kOdometryRestart), 1);
  const auto restart = std::find_if(events.begin(), events.end(), [](const InputEvent& e) {
    return e.kind == InputEvent::Kind::kOdometryRestart;
  });
  // After the restart, every new sample is handed on, in order.
  double last = -1;
  int after = 0;
  for (auto it = restart + 1; it != events.end(); ++it) {
    if (it->kind != InputEvent::Kind::kOdometry) continue;
    EXPECT_GT(it->t, last);
    last = it->t;
    ++after;
  }
  EXPECT_GT(after, 5);
  EXPECT_LT(restart->t, 0.4);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
