// Odometry and frames of a run directory, merged by time.
#include "tracker_agent/replay_input.h"

#include <thread>

namespace fleetloc::tracker_agent {

void Pacer::WaitUntil(double t) {
  if (!paced_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!wall_start_) wall_start_ = now, t_start_ = t;
  std::this_thread::sleep_until(*wall_start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                   std::chrono::duration<double>(t - t_start_)));
}

ReplayInput::ReplayInput(io::Run run, bool paced) : run_(std::move(run)), pacer_(paced) {}

Result<std::optional<InputEvent>> ReplayInput::Next() {
  const bool odometry_left = next_odometry_ < run_.odometry.size();
  const bool frames_left = next_frame_ < run_.frames.size();
  if (!odometry_left && !frames_left) return std::optional<InputEvent>();
  // Odometry first on equal times, so a frame always finds the sample at its own time.
  const bool take_odometry =
      odometry_left && (!frames_left || run_.odometry[next_odometry_].t <= run_.frames[next_frame_].t);
  InputEvent event;
  if (take_odometry) {
    const geometry::StampedPose& sample = run_.odometry[next_odometry_++];
    event.kind = InputEvent::Kind::kOdometry, event.t = sample.t, event.odom = sample.pose;
  } else {
    const io::FrameRef& ref = run_.frames[next_frame_++];
    event.kind = InputEvent::Kind::kFrame, event.t = ref.t;
    Result<cv::Mat> frame = run_.camera.raw ? io::ReadGrayImage(ref.file)
                                            : io::ReadFrame(ref, run_.camera.model);
    if (!frame.ok()) return frame.status();
    event.frame = std::move(frame).value();
  }
  pacer_.WaitUntil(event.t);
  return std::optional<InputEvent>(std::move(event));
}

}  // namespace fleetloc::tracker_agent
