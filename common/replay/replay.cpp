// Offline replay loop and accuracy statistics.
#include "replay/replay.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "rectification/camera_rectifier.h"
#include "tracking/odometry_history.h"

namespace fleetloc::replay {

using geometry::Pose2;

namespace {

Result<cv::Mat> ReadRunFrame(const run_io::FrameRef& ref, const run_io::Run& run,
                             const std::optional<calibration::Rectifier>& rectifier) {
  if (!rectifier) return run_io::ReadFrame(ref, run.camera.model);
  Result<cv::Mat> raw = run_io::ReadGrayImage(ref.file);
  if (!raw.ok()) return raw.status();
  return rectifier->Rectify(*raw);
}

}  // namespace

Result<ReplayResult> ReplayRun(const run_io::Run& run, tracking::FrameLocalizer& localizer,
                               const Progress& progress) {
  tracking::OdometryHistory odometry(1e12, 0.0);
  for (const auto& sample : run.odometry) FLEETLOC_RETURN_IF_ERROR(odometry.Add(sample));
  ReplayResult result;
  const std::optional<calibration::Rectifier> rectifier = rectification::RectifierFor(run.camera);
  const Eigen::Vector3d sigma = run.initial_sigma;
  for (size_t i = 0; i < run.frames.size(); ++i) {
    const run_io::FrameRef& ref = run.frames[i];
    Result<Pose2> odom = odometry.At(ref.t);
    if (!odom.ok())
      return InvalidInput(run.dir.string() + "/odometry.csv: " + odom.status().message());
    Result<cv::Mat> frame = ReadRunFrame(ref, run, rectifier);
    if (!frame.ok()) return frame.status();
    if (i == 0) {
      localizer.Reset({run.initial_pose, sigma.cwiseProduct(sigma).asDiagonal()}, *odom);
    }
    const auto start = std::chrono::steady_clock::now();
    const tracking::FrameResult r = localizer.Track(*frame, ref.t, *odom);
    const auto stop = std::chrono::steady_clock::now();
    result.cycle_ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
    result.poses.push_back({ref.t, r.base_in_map.pose, r.base_in_map.covariance,
                            tracking::LockStateName(r.state), r.inliers});
    result.frames.push_back(r);
    if (progress) progress(i + 1, run.frames.size());
  }
  return result;
}

namespace {

double Rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / v.size());
}

bool Locked(const std::string& status) { return status == "tracking" || status == "relocalized"; }

}  // namespace

Accuracy Evaluate(const std::vector<run_io::PoseRecord>& poses,
                  const std::vector<geometry::StampedPose>& truth,
                  const geometry::CameraModel& camera) {
  Accuracy a;
  a.frames = poses.size();
  std::vector<double> position, camera_position, heading;
  size_t locked = 0, unlocked_run = 0;
  for (size_t i = 0; i < poses.size() && i < truth.size(); ++i) {
    const Pose2& estimate = poses[i].pose;
    const Pose2& true_pose = truth[i].pose;
    if (poses[i].status == "lost") ++a.lost_frames;
    if (!Locked(poses[i].status)) {
      a.longest_unlocked_run = std::max(a.longest_unlocked_run, ++unlocked_run);
      continue;
    }
    unlocked_run = 0;
    ++locked;
    position.push_back(std::hypot(estimate.x - true_pose.x, estimate.y - true_pose.y));
    const Pose2 ce = estimate * camera.mount, ct = true_pose * camera.mount;
    camera_position.push_back(std::hypot(ce.x - ct.x, ce.y - ct.y));
    if (camera_position.back() > kFalseLockPx * camera.resolution_m) ++a.false_locks;
    heading.push_back(std::abs(geometry::WrapAngle(estimate.theta - true_pose.theta)));
  }
  a.lock_rate = poses.empty() ? 0.0 : static_cast<double>(locked) / poses.size();
  a.position_rms_m = Rms(position);
  a.position_p95_m = Percentile(position, 95);
  a.position_max_m = position.empty() ? 0 : *std::max_element(position.begin(), position.end());
  a.camera_position_rms_m = Rms(camera_position);
  a.camera_position_p95_m = Percentile(camera_position, 95);
  a.camera_position_max_m = camera_position.empty()
                                ? 0
                                : *std::max_element(camera_position.begin(), camera_position.end());
  a.heading_rms_rad = Rms(heading);
  a.heading_max_rad = heading.empty() ? 0 : *std::max_element(heading.begin(), heading.end());
  return a;
}

}  // namespace fleetloc::replay
