// The tracker agent's health as counted where it happens, without DDS: frames and their cycle
// times, inliers, lock state, dropped frames and the last error. AgentHealth turns these counts
// into a VehicleHealth message.
#pragma once

#include <deque>
#include <string>

#include "tracking/frame_localizer.h"

namespace fleetloc::tracker_agent {

class HealthCounters {
 public:
  void RecordFrame(const tracking::FrameResult& result, double cycle_ms);
  void RecordDroppedFrame(const std::string& error);
  void RecordError(const std::string& error);
  // A global relocalization attempt; a found pose makes the lock state `relocalized`.
  void RecordRelocalization(bool found);
  // The lock state changed without a frame (started without downward frames, a position update).
  void RecordLockState(tracking::LockState state) { state_ = state; }

  // Over the last `window` frames (at most 10,000).
  double CyclePercentile(double percent, size_t window = 200) const;
  long long frames() const { return frames_; }
  long long dropped_frames() const { return dropped_; }
  tracking::LockState lock_state() const { return state_; }
  int inliers() const { return inliers_; }
  const std::string& last_error() const { return last_error_; }

 private:
  std::deque<double> cycle_ms_;  // the last 10,000 frames (health uses the last 200)
  tracking::LockState state_ = tracking::LockState::kLost;
  int inliers_ = 0;
  long long frames_ = 0;
  long long dropped_ = 0;
  std::string last_error_;
};

}  // namespace fleetloc::tracker_agent
