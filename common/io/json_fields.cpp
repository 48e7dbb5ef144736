// Typed JSON member access with file and field named in every error.
#include "io/json_fields.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

#include "io/file_util.h"
#include "io/messages.h"

namespace fleetloc::io {
namespace {

using nlohmann::json;

std::string SizesText(std::initializer_list<std::size_t> sizes) {
  std::string text;
  for (std::size_t s : sizes) text += (text.empty() ? "" : " or ") + std::to_string(s);
  return text;
}

// nlohmann's messages start with "[json.exception.parse_error.101] "; keep what follows.
std::string ShortJsonError(const std::string& what) {
  const std::size_t close = what.find("] ");
  return close == std::string::npos ? what : what.substr(close + 2);
}

}  // namespace

Result<json> ReadJsonObjectFile(const std::filesystem::path& path) {
  Result<std::string> text = ReadFileText(path);
  if (!text.ok()) return text.status();
  json parsed;
  try {
    parsed = json::parse(*text);
  } catch (const json::parse_error& e) {
    const auto byte = static_cast<std::ptrdiff_t>(std::min<std::size_t>(e.byte, text->size()));
    const int line = 1 + static_cast<int>(std::count(text->begin(), text->begin() + byte, '\n'));
    return BadField(path, line, "", "invalid JSON: " + ShortJsonError(e.what()));
  } catch (const json::exception& e) {  // e.g. a number too large for a double (found by fuzzing)
    return BadField(path, 0, "", "invalid JSON: " + ShortJsonError(e.what()));
  }
  if (!parsed.is_object()) {
    return BadField(path, 0, "", std::string("expected a JSON object, got ") + parsed.type_name());
  }
  return parsed;
}

std::string DumpJson(const json& value, int indent) {
  return value.dump(indent, ' ', false, json::error_handler_t::replace);
}

Status WriteJsonFile(const std::filesystem::path& path, const json& object) {
  try {
    return WriteFileAtomically(path, object.dump(2) + "\n");
  } catch (const json::exception& e) {  // invalid UTF-8 in a string
    return InvalidInput(path.string() + ": cannot serialise JSON: " + ShortJsonError(e.what()));
  }
}

JsonFields::JsonFields(const json& object, std::filesystem::path file, std::string prefix)
    : object_(&object), file_(std::move(file)), prefix_(std::move(prefix)) {
  FLEETLOC_CHECK(object.is_object());
}

bool JsonFields::Has(std::string_view key) const {
  const auto it = object_->find(key);
  return it != object_->end() && !it->is_null();
}

Status JsonFields::RejectUnknown(std::initializer_list<std::string_view> known) const {
  for (const auto& [key, value] : object_->items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string list;
    for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    return Error(key, "unknown key (known: " + list + ")");
  }
  return Status::Ok();
}

Status JsonFields::Error(std::string_view key, std::string_view what) const {
  return BadField(file_, 0, prefix_ + std::string(key), what);
}

Status JsonFields::Find(std::string_view key, const json** value) const {
  const auto it = object_->find(key);
  if (it == object_->end()) return Error(key, "missing");
  if (it->is_null()) return Error(key, "is null");
  *value = &*it;
  return Status::Ok();
}

Status JsonFields::WrongType(std::string_view key, const json& value, std::string_view want) const {
  std::string got = value.type_name();
  if (value.is_primitive()) got.append(" ").append(value.dump());  // "number 16.5", "string \"16\""
  return Error(key, "expected " + std::string(want) + ", got " + got);
}

Status JsonFields::Number(std::string_view key, double* out) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find(key, &value));
  if (!value->is_number()) return WrongType(key, *value, "a number");
  *out = value->get<double>();
  if (!std::isfinite(*out)) return Error(key, "is not a finite number");
  return Status::Ok();
}

Status JsonFields::NonNegativeNumber(std::string_view key, double* out) const {
  FLEETLOC_RETURN_IF_ERROR(Number(key, out));
  if (*out < 0) return Error(key, "must not be negative, got " + FormatDouble(*out));
  return Status::Ok();
}

Status JsonFields::PositiveNumber(std::string_view key, double* out) const {
  FLEETLOC_RETURN_IF_ERROR(Number(key, out));
  if (*out <= 0) return Error(key, "must be positive, got " + FormatDouble(*out));
  return Status::Ok();
}

Status JsonFields::PositiveInt(std::string_view key, int* out) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find(key, &value));
  if (!value->is_number_integer()) return WrongType(key, *value, "an integer");
  // Parsed positive integers are stored unsigned, integers built in C++ signed: check both.
  const bool positive = value->is_number_unsigned() ? value->get<std::uint64_t>() > 0
                                                    : value->get<std::int64_t>() > 0;
  if (!positive) return Error(key, "must be positive, got " + value->dump());
  if (value->get<std::uint64_t>() > static_cast<std::uint64_t>(INT_MAX)) {
    return Error(key, "is too large: " + value->dump());
  }
  *out = value->get<int>();
  return Status::Ok();
}

Status JsonFields::NonEmptyString(std::string_view key, std::string* out) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find(key, &value));
  if (!value->is_string()) return WrongType(key, *value, "a string");
  *out = value->get<std::string>();
  if (out->empty()) return Error(key, "must not be empty");
  return Status::Ok();
}

Status JsonFields::Bool(std::string_view key, bool* out) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find(key, &value));
  if (!value->is_boolean()) return WrongType(key, *value, "true or false");
  *out = value->get<bool>();
  return Status::Ok();
}

Status JsonFields::Numbers(std::string_view key, std::initializer_list<std::size_t> sizes,
                           std::vector<double>* out) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find(key, &value));
  const std::string want = "an array of " + SizesText(sizes) + " numbers";
  if (!value->is_array()) return WrongType(key, *value, want);
  if (std::find(sizes.begin(), sizes.end(), value->size()) == sizes.end()) {
    return Error(key, "expected " + want + ", got " + std::to_string(value->size()) + " elements");
  }
  out->clear();
  for (std::size_t i = 0; i < value->size(); ++i) {
    const json& element = (*value)[i];
    const std::string name = std::string(key) + "[" + std::to_string(i) + "]";
    if (!element.is_number()) return WrongType(name, element, "a number");
    out->push_back(element.get<double>());
    if (!std::isfinite(out->back())) return Error(name, "is not a finite number");
  }
  return Status::Ok();
}

Result<JsonFields> JsonFields::Object(std::string_view key) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find(key, &value));
  if (!value->is_object()) return WrongType(key, *value, "an object");
  return JsonFields(*value, file_, prefix_ + std::string(key) + ".");
}

Status JsonFields::CheckFormat(std::string_view expected) const {
  const json* value = nullptr;
  FLEETLOC_RETURN_IF_ERROR(Find("format", &value));
  if (!value->is_string()) return WrongType("format", *value, "a string");
  if (value->get<std::string>() != expected) {
    return Error("format", "is '" + value->get<std::string>() + "', expected '" +
                               std::string(expected) + "'");
  }
  return Status::Ok();
}

}  // namespace fleetloc::io
