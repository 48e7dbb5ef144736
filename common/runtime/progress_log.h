// PercentLog: progress of long work as spdlog info lines, one each time another step of percent
// is done, so a gigapixel import or composition shows it is alive without flooding the log.
#pragma once

#include <string>

namespace fleetloc::runtime {

class PercentLog {
 public:
  // Lines read "<what>: <done> of <total> <unit> (<percent>%)". Requires 1 <= step_percent <= 100.
  PercentLog(std::string what, std::string unit, int step_percent = 10);

  // Reports `done` of `total` (total > 0); logs when a new step is reached and always at the end.
  void operator()(long long done, long long total);

 private:
  std::string what_;
  std::string unit_;
  int step_percent_;
  int last_step_ = -1;
};

}  // namespace fleetloc::runtime
