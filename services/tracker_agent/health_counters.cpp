// Health bookkeeping: what frames, drops and errors the agent counted.
#include "tracker_agent/health_counters.h"

#include "base/percentile.h"

namespace fleetloc::tracker_agent {

void HealthCounters::RecordFrame(const tracking::FrameResult& result, double cycle_ms) {
  cycle_ms_.push_back(cycle_ms);
  if (cycle_ms_.size() > 10000) cycle_ms_.pop_front();
  state_ = result.state;
  inliers_ = result.inliers;
  ++frames_;
}

void HealthCounters::RecordDroppedFrame(const std::string& error) {
  ++dropped_;
  last_error_ = error;
}

void HealthCounters::RecordError(const std::string& error) { last_error_ = error; }

void HealthCounters::RecordRelocalization(bool found) {
  if (found) state_ = tracking::LockState::kRelocalized;
}

double HealthCounters::CyclePercentile(double percent, size_t window) const {
  const size_t n = std::min(window, cycle_ms_.size());
  return Percentile({cycle_ms_.end() - static_cast<long>(n), cycle_ms_.end()}, percent);
}

}  // namespace fleetloc::tracker_agent
