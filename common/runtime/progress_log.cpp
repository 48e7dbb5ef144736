// Step-wise progress lines.
#include "runtime/progress_log.h"

#include <spdlog/spdlog.h>

#include <utility>

#include "base/status.h"

namespace fleetloc::runtime {

PercentLog::PercentLog(std::string what, std::string unit, int step_percent)
    : what_(std::move(what)), unit_(std::move(unit)), step_percent_(step_percent) {
  FLEETLOC_CHECK(step_percent >= 1 && step_percent <= 100);
}

void PercentLog::operator()(long long done, long long total) {
  FLEETLOC_CHECK(total > 0);
  const int percent = static_cast<int>(100 * done / total);
  const int step = percent / step_percent_;
  if (step == last_step_ && done != total) return;
  last_step_ = step;
  spdlog::info("{}: {} of {} {} ({}%)", what_, done, total, unit_, percent);
}

}  // namespace fleetloc::runtime
