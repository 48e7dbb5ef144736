// The VehiclePose samples an agent published, gathered by a test, and the one at a frame's time:
// shared by the agent integration tests that compare live poses with the offline tracker's.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "transport/pose_messages.h"

namespace fleetloc::testing {

// Takes every pose `reader` (a transport::VehicleStreamReader) has into `published`.
template <typename PoseReader>
void TakePoses(PoseReader& reader, std::vector<transport::PoseReport>* published) {
  (void)reader.TakeAll([&](const fleetloc_VehiclePose& pose, const dds_sample_info_t&) {
    published->push_back(transport::FromIdl(pose));
  });
}

// The published pose stamped at frame time `t` (to 2 ns), or nullptr.
inline const transport::PoseReport* PoseAt(const std::vector<transport::PoseReport>& published,
                                           double t) {
  const auto it =
      std::find_if(published.begin(), published.end(),
                   [&](const transport::PoseReport& r) { return std::abs(r.t - t) < 2e-9; });
  return it == published.end() ? nullptr : &*it;
}

}  // namespace fleetloc::testing
