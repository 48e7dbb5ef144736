// CaptureLatency: bounded histories of frame latencies and their percentiles.
#include "tracker_agent/capture_latency.h"

#include <algorithm>

#include "base/percentile.h"

namespace fleetloc::tracker_agent {
namespace {

constexpr const char* kStageNames[] = {"camera", "input", "before_cycle", "cycle_and_publish"};

void Push(std::deque<double>& history, double ms, size_t kept) {
  history.push_back(ms);
  if (history.size() > kept) history.pop_front();
}

nlohmann::json Percentiles(const std::vector<double>& v) {
  return nlohmann::json{{"frames", v.size()},
                        {"p50", v.empty() ? 0.0 : Percentile(v, 50)},
                        {"p99", v.empty() ? 0.0 : Percentile(v, 99)}};
}

}  // namespace

void CaptureLatency::Record(const FrameTimes& frame, double cycle_start, double published) {
  // Each stage ends where the next begins; one the source cannot time (0) is empty.
  const double arrival = frame.arrival > 0 ? frame.arrival : frame.capture;
  const double taken = frame.taken > 0 ? frame.taken : arrival;
  const std::array<double, kStages + 1> marks = {frame.capture, arrival, taken, cycle_start,
                                                 published};
  for (size_t i = 0; i < kStages; ++i)
    Push(stage_ms_[i], (marks[i + 1] - marks[i]) * 1000.0, kKept);
  Push(total_ms_, (published - frame.capture) * 1000.0, kKept);
  ++recorded_;
}

nlohmann::json CaptureLatency::Summary() const {
  const std::vector<double> latency(total_ms_.begin(), total_ms_.end());
  // The first kWarmupPoses of the stream that are still kept.
  const long long dropped_before = recorded_ - static_cast<long long>(latency.size());
  const size_t skip = static_cast<size_t>(
      std::clamp(kWarmupPoses - dropped_before, 0LL, static_cast<long long>(latency.size())));
  nlohmann::json all = Percentiles(latency);
  all["steady"] = Percentiles(std::vector<double>(latency.begin() + skip, latency.end()));
  all["steady"]["after_poses"] = kWarmupPoses;
  all["first_ms"] = std::vector<double>(latency.begin(), latency.begin() + skip);
  nlohmann::json stages = nlohmann::json::object();
  for (size_t i = 0; i < kStages; ++i)
    stages[kStageNames[i]] =
        Percentiles(std::vector<double>(stage_ms_[i].begin(), stage_ms_[i].end()));
  all["stages"] = stages;
  return all;
}

}  // namespace fleetloc::tracker_agent
