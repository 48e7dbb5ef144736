// Maps a device clock (a camera's timestamp counter, a GStreamer buffer's PTS) to the host clock
// from pairs (device time of capture, host time of arrival): host = device + offset, with the
// offset the smallest arrival − capture difference over a sliding window. Arrival is capture plus
// a transport delay that is never negative and sometimes near its minimum, so the minimum is the
// best bound on the offset (the convex-hull / minimum-delay filter of clock synchronization, e.g.
// the NTP clock filter, without its drift fit: the window lets a drifting device clock move the
// offset along). A device clock that restarts (a jump larger than `reset_s`) starts a new window.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>

namespace fleetloc::timing {

struct ClockMapperOptions {
  double window_s = 10.0;  // host time over which the minimum is taken
  double reset_s = 1.0;    // an offset more than this above or below the current one restarts
};

class ClockMapper {
 public:
  explicit ClockMapper(ClockMapperOptions options = {}) : options_(options) {}

  // Records one capture (device seconds) that arrived at `host_arrival_s` and returns its capture
  // time on the host clock (never after its arrival).
  double Map(double device_s, double host_arrival_s);
  // The current offset (host − device); nullopt before the first sample.
  std::optional<double> offset() const;
  long long resets() const { return resets_; }
  // Samples since the first or the last restart: the offset is only the smallest delay of these,
  // so the first few captures' times may be late by their whole transport delay.
  long long samples() const { return samples_; }

 private:
  struct Sample {
    double host_s;
    double offset_s;
  };
  ClockMapperOptions options_;
  std::deque<Sample> window_;  // increasing offsets (a monotonic deque: the front is the minimum)
  long long resets_ = 0;
  long long samples_ = 0;
};

}  // namespace fleetloc::timing
