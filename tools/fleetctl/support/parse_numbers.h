// Command-line lists of numbers such as "--origin 1.5,-2" or "--init 0.1,0,0.02", shared by the
// fleetctl subcommands.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::fleetctl {

// Parses exactly `count` comma-separated finite numbers. InvalidInput "<option>: expected <form>,
// got '<text>'" otherwise (NaN, infinities, blanks, too few or too many).
Result<std::vector<double>> ParseNumbers(const std::string& text, std::size_t count,
                                         const std::string& option, const std::string& form);

}  // namespace fleetloc::fleetctl
