// What the supervisor knows of a vehicle at one time: its newest pose and health, as plain values
// (the supervisor's DDS adapter converts the wire types into these).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "localization/lock_state.h"

namespace fleetloc::fleet {

// base_link in map (docs/formats.md) with the position and heading covariance, at time of validity
// t.
struct PoseSample {
  double t = 0.0;  // Unix seconds (the publisher's stamp)
  double x = 0.0, y = 0.0, theta = 0.0;
  double cov_xx = 0.0, cov_xy = 0.0, cov_yy = 0.0, cov_tt = 0.0;
  localization::LockState lock = localization::LockState::kLost;
  double localization_score = 0.0;  // 0..1
  double deviation_range_m = 0.0;   // 3 sigma of position
  long long mosaic_version = 0;
};

enum class HealthLevel { kOk, kWarn, kError, kStale };
const char* HealthLevelName(HealthLevel level);

struct HealthSample {
  double t = 0.0;  // Unix seconds
  HealthLevel level = HealthLevel::kOk;
  std::vector<std::string> issues;  // names of the reported issues
  localization::LockState lock = localization::LockState::kLost;
  double cycle_ms_p50 = 0.0, cycle_ms_p95 = 0.0, cycle_ms_p99 = 0.0;
  int inliers = 0;
  double cache_hit_rate = 1.0;
  int tiles_pending = 0;
  int patch_outbox = 0;
  bool map_server_reachable = true;
  std::uint64_t camera_frame_drops = 0;  // cumulative
  std::string last_error;
};

}  // namespace fleetloc::fleet
