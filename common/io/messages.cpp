// The one-line error format shared by every io reader.
#include "io/messages.h"

#include <charconv>
#include <system_error>

namespace fleetloc::io {

std::string Where(const std::filesystem::path& file, int line, std::string_view field) {
  std::string where = file.string();
  if (line > 0) where.append(":").append(std::to_string(line));
  where += ": ";
  if (!field.empty()) {
    where += "field '";
    where += field;
    where += "': ";
  }
  return where;
}

Status BadField(const std::filesystem::path& file, int line, std::string_view field,
                std::string_view what) {
  return InvalidInput(Where(file, line, field) + std::string(what));
}

std::string FormatDouble(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  FLEETLOC_CHECK(ec == std::errc());
  return std::string(buffer, end);
}

}  // namespace fleetloc::io
