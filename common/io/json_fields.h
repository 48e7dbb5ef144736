// Typed, validated access to the members of a JSON object for the io readers, with one-line errors
// "<file>: field '<dotted.name>': <what>". A known member of the wrong type or range is an error;
// readers reject unknown members with RejectUnknown (a typo must not leave a field at its default).
#pragma once

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.h"

namespace fleetloc::io {

// Parses a JSON file whose top level must be an object. NotFound when the file does not exist;
// InvalidInput "<file>:<line>: invalid JSON: ..." for a syntax error.
Result<nlohmann::json> ReadJsonObjectFile(const std::filesystem::path& path);

// Serialises `object` (pretty-printed, numbers round-trip exactly) and writes it atomically.
// `value` as JSON text; bytes of strings that are not valid UTF-8 (e.g. from another participant
// or an HTTP request) become U+FFFD instead of throwing (nlohmann's default).
std::string DumpJson(const nlohmann::json& value, int indent = -1);

Status WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& object);

// A view of one JSON object inside a file. Holds a pointer: the json must outlive the view.
class JsonFields {
 public:
  // `object` must be a JSON object (checked). `prefix` names it in messages ("mount.").
  JsonFields(const nlohmann::json& object, std::filesystem::path file, std::string prefix = "");

  // True when the member exists and is not null.
  bool Has(std::string_view key) const;
  // Each getter requires the member to exist with the right type and range.
  Status Number(std::string_view key, double* out) const;  // finite
  Status NonNegativeNumber(std::string_view key, double* out) const;
  Status PositiveNumber(std::string_view key, double* out) const;
  Status PositiveInt(std::string_view key, int* out) const;
  Status NonEmptyString(std::string_view key, std::string* out) const;
  Status Bool(std::string_view key, bool* out) const;  // true or false
  // An array of finite numbers whose length is one of `sizes`.
  Status Numbers(std::string_view key, std::initializer_list<std::size_t> sizes,
                 std::vector<double>* out) const;
  // The member must be a JSON object; the returned view prefixes its members' names.
  Result<JsonFields> Object(std::string_view key) const;
  // The member "format" must be the string `expected`.
  Status CheckFormat(std::string_view expected) const;
  // InvalidInput naming the first member not in `known`: "field '<key>': unknown key (known: ...)".
  Status RejectUnknown(std::initializer_list<std::string_view> known) const;

  // InvalidInput "<file>: field '<prefix><key>': <what>".
  Status Error(std::string_view key, std::string_view what) const;

 private:
  // The member, or an error when it is absent or null.
  Status Find(std::string_view key, const nlohmann::json** value) const;
  Status WrongType(std::string_view key, const nlohmann::json& value, std::string_view want) const;

  const nlohmann::json* object_;
  std::filesystem::path file_;
  std::string prefix_;
};

}  // namespace fleetloc::io
