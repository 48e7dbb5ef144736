// Offline replay of a run directory through a FrameLocalizer, exactly as the agent feeds it live:
// odometry interpolated at each frame's time, frames read and checked one by one, and the
// accuracy against truth.csv when the run has one.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "base/percentile.h"
#include "run_io/run.h"
#include "tracking/frame_localizer.h"

namespace fleetloc::replay {

struct ReplayResult {
  std::vector<run_io::PoseRecord> poses;      // one per frame, in frame order
  std::vector<double> cycle_ms;               // time inside the localizer per frame
  std::vector<tracking::FrameResult> frames;  // the localizer's own account of each frame
};

using Progress = std::function<void(size_t done, size_t total)>;

// Replays every frame (rectified first when the camera is raw: rectification::RectifierFor). A
// frame image that cannot be read or has the wrong size is bad input: the run is rejected with that
// file's error (exit status 2), nothing is half-reported.
Result<ReplayResult> ReplayRun(const run_io::Run& run, tracking::FrameLocalizer& localizer,
                               const Progress& progress = {});

// Accuracy of base_link (and of the camera, which the tracker measures directly) against truth.
struct Accuracy {
  size_t frames = 0;
  double position_rms_m = 0, position_p95_m = 0, position_max_m = 0;
  double camera_position_rms_m = 0, camera_position_p95_m = 0;
  double heading_rms_rad = 0, heading_max_rad = 0;
  double lock_rate = 0;  // fraction of frames tracking or relocalized
  size_t lost_frames = 0;
  size_t longest_unlocked_run = 0;  // consecutive frames not tracking
  // Locked frames whose camera footprint centre (what the tracker measures) is more than
  // kFalseLockPx camera pixels from the truth: the frame claimed a pose it did not have.
  size_t false_locks = 0;
  double camera_position_max_m = 0;
};

inline constexpr double kFalseLockPx = 1.0;

// Requires truth with one row per pose (same order). Errors are taken over the locked frames
// (tracking/relocalized); the lock rate and unlocked runs say how many those are.
Accuracy Evaluate(const std::vector<run_io::PoseRecord>& poses,
                  const std::vector<geometry::StampedPose>& truth,
                  const geometry::CameraModel& camera);

// Percentile (0..100) of a sample, base/percentile.h; replay::Percentile for the tools' reports.
using ::fleetloc::Percentile;

}  // namespace fleetloc::replay
