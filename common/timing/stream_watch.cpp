// Live stream bookkeeping: verdicts, silence, recent trouble, counts that rose lately.
#include "timing/stream_watch.h"

namespace fleetloc::timing {

SampleVerdict StreamWatch::Check(double t_s, bool finite, double host_s) {
  last_arrival_host_s_ = host_s;
  SampleVerdict verdict = SampleVerdict::kOk;
  if (!finite) {
    verdict = SampleVerdict::kNotFinite;
  } else if (last_good_t_ && t_s <= *last_good_t_) {
    verdict = SampleVerdict::kBackInTime;
  }
  ++counts_[static_cast<int>(verdict)];
  if (verdict == SampleVerdict::kOk) {
    last_good_t_ = t_s;
  } else {
    last_bad_host_s_[static_cast<int>(verdict)] = host_s;
  }
  return verdict;
}

bool StreamWatch::Stale(double host_s) const {
  return host_s - last_arrival_host_s_.value_or(started_host_s_) > stale_after_s_;
}

bool StreamWatch::Recent(SampleVerdict verdict, double host_s) const {
  return host_s - last_bad_host_s_[static_cast<int>(verdict)] <= hold_s_;
}

bool CountWatch::Recent(long long count, double host_s) {
  if (count > last_count_) rose_host_s_ = host_s;
  last_count_ = count;
  return host_s - rose_host_s_ <= hold_s_;
}

const char* VerdictName(SampleVerdict verdict) {
  switch (verdict) {
    case SampleVerdict::kOk:
      return "ok";
    case SampleVerdict::kNotFinite:
      return "not_finite";
    case SampleVerdict::kBackInTime:
      return "back_in_time";
  }
  return "?";
}

}  // namespace fleetloc::timing
