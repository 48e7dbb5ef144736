// fleetctl bench agent --source aravis: a live vehicle end to end — the simulated drive served by
// Aravis's fake GigE Vision camera on 127.0.0.1, odometry and the start pose as ROS 2 messages —
// through map_server and tracker_agent processes: capture → pose-on-the-wire latency (p50/p99)
// and the live accuracy against the offline tracker's on the same frames.
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::fleetctl {

struct LiveAgentBenchSettings {
  std::string work_dir;
  int frames = 300;
  double rate_hz = 10.0;
  int domain = 92;
  std::string json;
};

Status RunLiveAgentBench(const LiveAgentBenchSettings& settings);

}  // namespace fleetloc::fleetctl
