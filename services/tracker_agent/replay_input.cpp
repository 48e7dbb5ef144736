// Odometry and frames of a run directory, merged by time.
#include "tracker_agent/replay_input.h"

#include <thread>

namespace fleetloc::tracker_agent {

void Pacer::WaitUntil(double t) {
  if (!paced_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!wall_start_) {
    wall_start_ = now;
    t_start_ = t;
  }
  std::this_thread::sleep_until(*wall_start_ +
                                std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(t - t_start_)));
}

ReplayInput::ReplayInput(run_io::Run run, bool paced) : run_(std::move(run)), pacer_(paced) {}

std::optional<std::pair<InputEvent::Kind, double>> ReplayInput::Peek() const {
  using Kind = InputEvent::Kind;
  std::optional<std::pair<Kind, double>> next;
  auto consider = [&](Kind kind, bool left, auto time) {  // earlier wins, ties keep the first
    if (left && (!next || time() < next->second)) next = std::pair{kind, time()};
  };
  consider(Kind::kOdometry, next_odometry_ < run_.odometry.size(),
           [&] { return run_.odometry[next_odometry_].t; });
  consider(Kind::kFrame, next_frame_ < run_.frames.size(),
           [&] { return run_.frames[next_frame_].t; });
  const std::vector<run_io::FrameRef>* forward = run_.forward ? &run_.forward->frames : nullptr;
  consider(Kind::kForwardFrame, forward && next_forward_ < forward->size(),
           [&] { return (*forward)[next_forward_].t; });
  return next;
}

Result<cv::Mat> ReplayInput::ReadFrame(const run_io::FrameRef& ref) const {
  return run_.camera.raw ? run_io::ReadGrayImage(ref.file)
                         : run_io::ReadFrame(ref, run_.camera.model);
}

Result<std::optional<InputEvent>> ReplayInput::Next() {
  const std::optional<std::pair<InputEvent::Kind, double>> next = Peek();
  if (!next) return std::optional<InputEvent>();
  InputEvent event;
  event.kind = next->first;
  event.t = next->second;
  switch (event.kind) {
    case InputEvent::Kind::kOdometry:
      event.odom = run_.odometry[next_odometry_++].pose;
      break;
    case InputEvent::Kind::kFrame: {
      Result<cv::Mat> frame = ReadFrame(run_.frames[next_frame_++]);
      if (!frame.ok()) return frame.status();
      event.frame = std::move(frame).value();
      break;
    }
    case InputEvent::Kind::kForwardFrame: {
      Result<cv::Mat> image = run_io::ReadGrayImage(run_.forward->frames[next_forward_++].file);
      if (!image.ok()) {
        return Status(image.status().code(), "forward camera: " + image.status().message());
      }
      event.frame = std::move(image).value();
      break;
    }
    case InputEvent::Kind::kIdle:  // a replay always has its next event: Peek gives neither
    case InputEvent::Kind::kOdometryRestart:
      break;
  }
  pacer_.WaitUntil(event.t);
  return std::optional<InputEvent>(std::move(event));
}

}  // namespace fleetloc::tracker_agent
