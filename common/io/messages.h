// The one-line error format shared by every io reader (docs/formats.md: name the file, line and
// field).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "base/status.h"

namespace fleetloc::io {

// "<file>:<line>: field '<field>': " — the line is omitted when `line` <= 0 and the field part
// when `field` is empty, giving "<file>: " at the least.
std::string Where(const std::filesystem::path& file, int line, std::string_view field);

// InvalidInput(Where(file, line, field) + what).
Status BadField(const std::filesystem::path& file, int line, std::string_view field,
                std::string_view what);

// Shortest decimal text that parses back to exactly `value` (std::to_chars): "0.1", "1e-05",
// "nan", "inf". Used for numbers in files and in messages.
std::string FormatDouble(double value);

}  // namespace fleetloc::io
