// Command-line lists of numbers (see parse_numbers.h).
#include "support/parse_numbers.h"

#include <charconv>
#include <cmath>

namespace fleetloc::fleetctl {

Result<std::vector<double>> ParseNumbers(const std::string& text, std::size_t count,
                                         const std::string& option, const std::string& form) {
  std::vector<double> numbers;
  const char* at = text.data();
  const char* end = text.data() + text.size();
  while (at <= end && numbers.size() <= count) {
    double value = 0;
    const auto [next, ec] = std::from_chars(at, end, value);
    if (ec != std::errc() || !std::isfinite(value) || (next != end && *next != ',')) break;
    numbers.push_back(value);
    at = next + 1;
  }
  if (numbers.size() != count || at != end + 1) {
    return InvalidInput(option + ": expected " + form + ", got '" + text + "'");
  }
  return numbers;
}

}  // namespace fleetloc::fleetctl
