// Live camera thread and ROS 2 odometry merged into vehicle input events.
#include "tracker_agent/live_input.h"

#include <spdlog/spdlog.h>

#include <cmath>

#include "camera_io/aravis_camera.h"
#include "camera_io/gst_camera.h"

namespace fleetloc::tracker_agent {

using camera_io::HostNow;
using timing::SampleVerdict;

LiveInput::LiveInput(const AgentConfig& config, const run_io::CameraFile& camera,
                     CameraOpener opener)
    : options_(config.live),
      vehicle_id_(config.vehicle_id),
      expected_size_(camera.raw ? cv::Size()
                                : cv::Size(camera.model.width_px, camera.model.height_px)),
      opener_(std::move(opener)),
      odometry_watch_(config.live.odometry_stale_s, config.live.issue_hold_s),
      camera_watch_(config.live.camera_stall_s, config.live.issue_hold_s),
      packet_loss_watch_(config.live.issue_hold_s) {}

LiveInput::CameraOpener LiveInput::OpenerFor(const AgentConfig& config) {
  if (config.source == "aravis") {
    return [options = config.live.aravis]() -> Result<std::unique_ptr<camera_io::CameraSource>> {
      auto camera = camera_io::AravisCamera::Open(options);
      if (!camera.ok()) return camera.status();
      return std::unique_ptr<camera_io::CameraSource>(std::move(camera).value());
    };
  }
  return [options = config.live.gstreamer]() -> Result<std::unique_ptr<camera_io::CameraSource>> {
    auto camera = camera_io::GstCamera::Open(options);
    if (!camera.ok()) return camera.status();
    return std::unique_ptr<camera_io::CameraSource>(std::move(camera).value());
  };
}

Result<std::unique_ptr<LiveInput>> LiveInput::Create(const AgentConfig& config,
                                                     const run_io::CameraFile& camera,
                                                     CameraOpener opener) {
  std::unique_ptr<LiveInput> input(new LiveInput(config, camera, std::move(opener)));
  FLEETLOC_RETURN_IF_ERROR(
      AssignTo(transport::Participant::Create(config.domain_id, {"", config.dds_config_path}),
               &input->participant_));
  auto odometry = RosOdometryReader::Create(*input->participant_, config.ros);
  if (!odometry.ok()) return odometry.status();
  input->odometry_ = std::move(odometry).value();
  const double now = HostNow();
  input->odometry_watch_.Start(now);
  input->camera_watch_.Start(now);
  input->camera_thread_ = std::thread([raw = input.get()] { raw->CameraLoop(); });
  return input;
}

LiveInput::~LiveInput() {
  stop_.store(true);
  if (camera_thread_.joinable()) camera_thread_.join();
  if (closer_.joinable()) closer_.join();
}

void LiveInput::SetCameraError(const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (error == camera_error_) return;
  if (error.empty()) {
    spdlog::info("camera available again");
  } else {
    spdlog::error("camera unavailable: {}", error);
  }
  camera_error_ = error;
}

void LiveInput::CameraLoop() {
  std::unique_ptr<camera_io::CameraSource> camera;
  double last_frame_host = HostNow();
  auto close = [&](const std::string& why) {
    SetCameraError(why);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const camera_io::CameraStats s = camera->stats();
      closed_stats_.frames += s.frames;
      closed_stats_.dropped += s.dropped;
      closed_stats_.lost_packets += s.lost_packets;
      closed_stats_.resent_packets += s.resent_packets;
      camera_stats_ = {};
    }
    // Closed on a thread of its own: closing a GigE Vision camera that is gone waits out its
    // control channel's timeouts (Aravis: 5 tries of 500 ms a command, 3-12 s measured, or until
    // the camera answers again), and the reopening must not wait for that.
    if (closer_.joinable()) closer_.join();
    closer_ = std::thread([old = std::move(camera)]() mutable { old.reset(); });
  };
  while (!stop_.load()) {
    if (!camera) {
      auto opened = opener_();
      if (!opened.ok()) {
        SetCameraError(opened.status().message());
        for (int i = 0; i < 10 && !stop_.load(); ++i)
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      camera = std::move(opened).value();
      spdlog::info("camera open: {}", camera->Describe());
      SetCameraError("");
      last_frame_host = HostNow();
    }
    Result<std::optional<camera_io::CapturedFrame>> grabbed = camera->Grab(0.1);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const long long before = camera_stats_.dropped;
      camera_stats_ = camera->stats();
      if (camera_stats_.dropped > before && HostNow() - last_drop_log_ > 1.0) {
        spdlog::warn("camera dropped a frame ({} from this camera so far): {}",
                     camera_stats_.dropped, camera_stats_.last_drop);
        last_drop_log_ = HostNow();
      }
    }
    if (!grabbed.ok()) {
      close(grabbed.status().message());
      continue;
    }
    const double now = HostNow();
    if (grabbed->has_value()) {
      last_frame_host = now;
      Accept(std::move(grabbed->value()));
    } else if (now - last_frame_host > options_.camera_reopen_s) {
      spdlog::warn("camera stalled: no frame for {:.1f} s, reopening {}", now - last_frame_host,
                   camera->Describe());
      close(fmt::format("stalled: no frame for {:.1f} s; reopening", now - last_frame_host));
    }
  }
}

void LiveInput::DropFrame(const std::string& why, bool wrong_format) {
  ++dropped_;  // mutex_ held
  const double now = HostNow();
  if (now - last_drop_log_ > 1.0) {
    spdlog::warn("camera frame dropped: {}", why);
    last_drop_log_ = now;
  }
  if (wrong_format) {
    wrong_format_ = why;
    wrong_format_host_s_ = now;
  }
}

void LiveInput::Accept(camera_io::CapturedFrame frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  const cv::Size size = frame.image.size();
  if (expected_size_.empty()) expected_size_ = size;  // a raw camera: the first frame's size
  if (size != expected_size_) {
    return DropFrame("frame " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                         ", camera.json expects " + std::to_string(expected_size_.width) + "x" +
                         std::to_string(expected_size_.height),
                     true);
  }
  // A frame time that is not finite, or not after the previous frame's (a repeat or a clock that
  // went back), is dropped and named (camera_time_not_finite, camera_back_in_time): the tracker
  // runs frames in time order only. Not a wrong format: the image itself is fine.
  switch (camera_watch_.Check(frame.t, std::isfinite(frame.t), frame.arrival_t)) {
    case SampleVerdict::kOk:
      break;
    case SampleVerdict::kNotFinite:
      return DropFrame("frame time is not finite", false);
    case SampleVerdict::kBackInTime:
      return DropFrame(fmt::format("frame time {:.6f} not after the previous frame's {:.6f}",
                                   frame.t, camera_watch_.last_good_t().value_or(NAN)),
                       false);
  }
  if (frames_.size() >= static_cast<size_t>(options_.frame_queue)) {
    frames_.pop_front();
    DropFrame("the tracker is behind", false);
  }
  frames_.push_back(std::move(frame));
  frame_ready_.notify_one();
}

void LiveInput::TakeOdometry() {
  Result<std::vector<transport::RosOdometry>> taken = odometry_->Take();
  if (!taken.ok()) {
    spdlog::warn("odometry: {}", taken.status().message());
    return;
  }
  const double now = HostNow();
  for (const transport::RosOdometry& sample : *taken) {
    const SampleVerdict verdict =
        odometry_watch_.Check(sample.t, sample.finite && std::isfinite(sample.t), now);
    if (verdict == SampleVerdict::kOk) {
      if (odometry_bad_since_ >= 0) spdlog::info("odometry good again at t={:.3f}", sample.t);
      odometry_bad_since_ = -1;
      InputEvent event;
      event.kind = InputEvent::Kind::kOdometry;
      event.t = sample.t;
      event.odom = sample.pose;
      ready_.push_back(event);
      latest_odometry_ = std::pair{sample.t, sample.pose};
      continue;
    }
    if (odometry_bad_since_ < 0) {
      odometry_bad_since_ = now;
      spdlog::warn("odometry sample dropped ({}): t={:.6f}, last good t={:.6f}",
                   timing::VerdictName(verdict), sample.t,
                   odometry_watch_.last_good_t().value_or(NAN));
    }
    if (verdict == SampleVerdict::kBackInTime &&
        now - odometry_bad_since_ > options_.odometry_stale_s) {
      // Only older times for a while: the odometry source restarted with a new clock.
      spdlog::warn("odometry restarted: t={:.6f} after {:.6f}; a new odometry history begins",
                   sample.t, odometry_watch_.last_good_t().value_or(NAN));
      odometry_watch_ = timing::StreamWatch(options_.odometry_stale_s, options_.issue_hold_s);
      odometry_watch_.Check(sample.t, true, now);
      odometry_bad_since_ = -1;
      InputEvent restart;
      restart.kind = InputEvent::Kind::kOdometryRestart;
      restart.t = sample.t;
      ready_.push_back(restart);
      InputEvent event;
      event.kind = InputEvent::Kind::kOdometry;
      event.t = sample.t;
      event.odom = sample.pose;
      ready_.push_back(event);
      latest_odometry_ = std::pair{sample.t, sample.pose};
    }
  }
  const bool stale = odometry_watch_.Stale(now);
  if (stale != odometry_was_stale_) {
    if (stale) {
      spdlog::error("odometry stale: nothing on {} for {:.1f} s", odometry_->topic_name(),
                    options_.odometry_stale_s);
    } else {
      spdlog::info("odometry flowing again on {}", odometry_->topic_name());
    }
    odometry_was_stale_ = stale;
  }
}

Result<std::optional<InputEvent>> LiveInput::Next() {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
  for (;;) {
    if (ready_.empty()) TakeOdometry();
    if (!ready_.empty()) {
      InputEvent event = std::move(ready_.front());
      ready_.pop_front();
      return std::optional<InputEvent>(std::move(event));
    }
    std::unique_lock<std::mutex> lock(mutex_);
    if (!frames_.empty()) {
      InputEvent event;
      event.kind = InputEvent::Kind::kFrame;
      event.t = frames_.front().t;
      event.frame = std::move(frames_.front().image);
      event.arrival_t = frames_.front().arrival_t;
      event.taken_t = HostNow();
      frames_.pop_front();
      return std::optional<InputEvent>(std::move(event));
    }
    if (std::chrono::steady_clock::now() >= deadline) break;
    frame_ready_.wait_for(lock, std::chrono::milliseconds(2));
  }
  InputEvent idle;
  idle.kind = InputEvent::Kind::kIdle;
  return std::optional<InputEvent>(std::move(idle));
}

long long LiveInput::DroppedFrames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_ + closed_stats_.dropped + camera_stats_.dropped;
}

std::vector<InputIssue> LiveInput::Issues() const {
  const double now = HostNow();
  std::vector<InputIssue> issues;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!camera_error_.empty()) {
    issues.push_back({"camera_unavailable", true, camera_error_});
  } else if (camera_watch_.Stale(now)) {
    issues.push_back(
        {"camera_stalled", true, "no frame for " + std::to_string(options_.camera_stall_s) + " s"});
  }
  if (now - wrong_format_host_s_ <= options_.issue_hold_s)
    issues.push_back({"camera_wrong_format", false, wrong_format_});
  if (camera_watch_.Recent(SampleVerdict::kBackInTime, now)) {
    issues.push_back({"camera_back_in_time", false,
                      std::to_string(camera_watch_.count(SampleVerdict::kBackInTime)) +
                          " frames not after the previous frame's time dropped"});
  }
  if (camera_watch_.Recent(SampleVerdict::kNotFinite, now)) {
    issues.push_back({"camera_time_not_finite", false,
                      std::to_string(camera_watch_.count(SampleVerdict::kNotFinite)) +
                          " frames with a NaN or infinite time dropped"});
  }
  const long long lost = closed_stats_.lost_packets + camera_stats_.lost_packets;
  const long long resent = closed_stats_.resent_packets + camera_stats_.resent_packets;
  if (packet_loss_watch_.Recent(lost + resent, now)) {
    issues.push_back(
        {"camera_packet_loss", false,
         std::to_string(lost) + " packets lost, " + std::to_string(resent) + " resent"});
  }
  if (odometry_watch_.Stale(now)) {
    issues.push_back({"odometry_stale", true, "no odometry on " + odometry_->topic_name()});
  }
  if (odometry_watch_.Recent(SampleVerdict::kBackInTime, now)) {
    issues.push_back({"odometry_back_in_time", false,
                      std::to_string(odometry_watch_.count(SampleVerdict::kBackInTime)) +
                          " samples older than the last one dropped"});
  }
  if (odometry_watch_.Recent(SampleVerdict::kNotFinite, now)) {
    issues.push_back({"odometry_not_finite", false,
                      std::to_string(odometry_watch_.count(SampleVerdict::kNotFinite)) +
                          " samples with NaN or infinite values dropped"});
  }
  return issues;
}

}  // namespace fleetloc::tracker_agent
