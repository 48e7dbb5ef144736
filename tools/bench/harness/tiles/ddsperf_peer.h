// Cyclone's own ddsperf as the peer of the tile benchmark: pub/sub throughput and ping-pong
// round-trip time for a given sample size, as two processes on their own domain.
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::bench {

struct DdsperfThroughput {
  double samples_per_s = 0;  // median of the per-second rates after the first second
  double megabytes_per_s = 0;
};
struct DdsperfLatency {
  double rtt_p50_us = 0;
  double rtt_p99_us = 0;
};

// `config_uri`: CYCLONEDDS_URI for both processes; logs go to `work_dir`. NotFound if ddsperf is
// not installed; Internal if its output has no rates.
Result<DdsperfThroughput> RunDdsperfThroughput(int domain, int size_bytes, double seconds,
                                               const std::string& config_uri,
                                               const std::string& work_dir);
Result<DdsperfLatency> RunDdsperfPingPong(int domain, int size_bytes, double seconds,
                                          const std::string& config_uri,
                                          const std::string& work_dir);

}  // namespace fleetloc::bench
