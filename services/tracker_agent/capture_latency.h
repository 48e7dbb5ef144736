// A live agent's capture -> pose-on-the-wire latency, in total and stage by stage, so that a slow
// pose says where its time went: the camera (capture to the buffer's arrival in this process), the
// input (arrival to the agent's loop taking the frame: conversion, the camera thread, the queue),
// before the cycle (rectification, waiting for odometry to cover the frame, tiles) and the cycle
// itself with the publishing. All times on the host clock, seconds.
#pragma once

#include <array>
#include <deque>
#include <nlohmann/json.hpp>
#include <vector>

namespace fleetloc::tracker_agent {

// A frame's times on its way to the tracker (0 where the source cannot tell).
struct FrameTimes {
  double capture = 0.0;  // the frame's stamp
  double arrival = 0.0;  // its buffer reached this process
  double taken = 0.0;    // the agent's loop took it from the input
};

class CaptureLatency {
 public:
  static constexpr long long kWarmupPoses = 20;  // excluded from "steady"
  static constexpr size_t kKept = 10000;         // the last latencies kept

  // One frame's pose put on the wire at `published`; its tracker cycle began at `cycle_start`.
  void Record(const FrameTimes& frame, double cycle_start, double published);
  // p50/p99 in ms over the kept poses and over those after the first kWarmupPoses ("steady":
  // tiles cached, caches warm), those first ones themselves ("first_ms"), and per stage
  // ("stages": camera, input, before_cycle, cycle_and_publish; stages a source cannot time, e.g.
  // the arrival of a frame without one, count in the next stage).
  nlohmann::json Summary() const;

 private:
  static constexpr size_t kStages = 4;
  std::deque<double> total_ms_;
  std::array<std::deque<double>, kStages> stage_ms_;
  long long recorded_ = 0;
};

}  // namespace fleetloc::tracker_agent
