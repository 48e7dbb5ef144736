// fleetctl bench agent --source aravis|gstreamer: a live vehicle end to end — the simulated drive
// served by Aravis's fake GigE Vision camera on 127.0.0.1 (read by the agent's Aravis source, or
// by a GStreamer aravissrc pipeline), odometry and the start pose as ROS 2 messages — through
// map_server and tracker_agent processes: capture → pose-on-the-wire latency (p50/p99, all frames
// and after the first 20) and the live accuracy against the offline tracker's on the same frames.
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::bench {

struct LiveAgentBenchSettings {
  std::string work_dir;
  int frames = 300;
  double rate_hz = 10.0;
  int domain = 92;
  std::string json;
  std::string source = "aravis";           // or "gstreamer" (aravissrc)
  double odometry_extrapolation_s = 0.02;  // the agent's live.odometry_extrapolation_s
  // gstreamer: "device" (aravissrc's PTS, the camera's clock, mapped by gstreamer.timestamps
  // device) or "created" (aravissrc do-timestamp=true: stamped when the buffer is created).
  std::string gstreamer_timestamps = "device";
};

Status RunLiveAgentBench(const LiveAgentBenchSettings& settings);

}  // namespace fleetloc::bench
