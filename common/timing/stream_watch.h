// Watches one live input stream (a camera's frames, odometry samples) for what a vehicle's
// integrator must hear about: silence (nothing for `stale_after_s` of host time), samples that
// are not finite, and sample times that go backwards. Each bad sample is named by its verdict;
// the watch remembers when each kind last happened so health can report it for a while after
// (`hold_s`) and then clear it: the stream has recovered.
#pragma once

#include <optional>
#include <string>

namespace fleetloc::timing {

enum class SampleVerdict { kOk, kNotFinite, kBackInTime };

class StreamWatch {
 public:
  StreamWatch(double stale_after_s, double hold_s)
      : stale_after_s_(stale_after_s), hold_s_(hold_s) {}

  // One sample of time `t_s` (its own clock), `finite` when all its values are, arriving at host
  // time `host_s`. kOk samples must be used, the others dropped. A sample at the same time as
  // the last good one is kBackInTime (a repeat).
  SampleVerdict Check(double t_s, bool finite, double host_s);
  // Silent since the last sample (or since `started_host_s` before any) for stale_after_s.
  bool Stale(double host_s) const;
  // A bad sample of this kind within the last hold_s.
  bool Recent(SampleVerdict verdict, double host_s) const;
  void Start(double host_s) { started_host_s_ = host_s; }
  long long count(SampleVerdict verdict) const { return counts_[static_cast<int>(verdict)]; }
  std::optional<double> last_good_t() const { return last_good_t_; }

 private:
  double stale_after_s_, hold_s_;
  double started_host_s_ = 0.0;
  std::optional<double> last_good_t_;
  std::optional<double> last_arrival_host_s_;
  double last_bad_host_s_[3] = {-1e300, -1e300, -1e300};
  long long counts_[3] = {0, 0, 0};
};

// A running count of trouble (packets lost, frames dropped, tile waits timed out) turned into an
// issue that holds for `hold_s` after the count last rose and then clears, as StreamWatch's
// per-sample issues do: a packet lost an hour ago is no longer news. The count itself stays in the
// health figures and the log.
class CountWatch {
 public:
  explicit CountWatch(double hold_s) : hold_s_(hold_s) {}
  // The count as of host time `host_s`: whether it rose within the last hold_s. A count lower
  // than the last one (its source restarted) is taken as the new base.
  bool Recent(long long count, double host_s);

 private:
  double hold_s_;
  long long last_count_ = 0;
  double rose_host_s_ = -1e300;
};

// "ok", "not_finite", "back_in_time".
const char* VerdictName(SampleVerdict verdict);

}  // namespace fleetloc::timing
