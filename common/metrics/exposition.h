// A strict reader of the Prometheus text exposition format (version 0.0.4), for the tests that
// scrape the services: every line must be a HELP, TYPE or comment line, a sample of a family whose
// TYPE came first, or empty. It checks names, label syntax and escapes, values, duplicate TYPE
// lines and histogram shape (le labels, ascending, cumulative, +Inf equal to _count).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.h"

namespace fleetloc::metrics {

struct Sample {
  std::string name;  // as written (with _bucket/_sum/_count/_total)
  std::map<std::string, std::string> labels;
  double value = 0.0;
};

struct Exposition {
  std::vector<Sample> samples;
  std::map<std::string, std::string>
      types;  // family name -> counter|gauge|histogram|summary|untyped

  // The value of the first sample named `name` whose labels include every one of `labels`;
  // NotFound naming it otherwise.
  Result<double> Value(const std::string& name,
                       const std::map<std::string, std::string>& labels = {}) const;
};

// InvalidInput "line N: <what>" at the first line that breaks the format.
Result<Exposition> ParseExposition(std::string_view text);

}  // namespace fleetloc::metrics
