// Mosaic metadata parsing and validation.
#include "mosaic/mosaic_metadata.h"

#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>

#include "mosaic/tile_key.h"

namespace fleetloc::mosaic {
namespace {

constexpr int kMaxSizePx = 1 << 24;

std::string FormatDouble(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

bool IsHexId(const std::string& id) {
  if (id.size() != 32) return false;
  for (const char c : id) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

Result<std::string> Field(const Metadata& metadata, const std::string& key) {
  const auto it = metadata.find(key);
  if (it == metadata.end()) return InvalidInput("metadata key '" + key + "' is missing");
  return it->second;
}

Status OutOfRange(const std::string& key, const std::string& value, const std::string& what) {
  return InvalidInput("metadata '" + key + "' = '" + value + "' " + what);
}

// An integer in [min_value, max_value]; the whole string must be the number.
Result<long long> IntField(const Metadata& metadata, const std::string& key, long long min_value,
                           long long max_value) {
  Result<std::string> text = Field(metadata, key);
  if (!text.ok()) return text.status();
  long long value = 0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (ec != std::errc() || ptr != end) return OutOfRange(key, *text, "is not an integer");
  if (value < min_value || value > max_value) {
    return OutOfRange(
        key, *text,
        "is outside [" + std::to_string(min_value) + ", " + std::to_string(max_value) + "]");
  }
  return value;
}

Result<double> FiniteField(const Metadata& metadata, const std::string& key) {
  Result<std::string> text = Field(metadata, key);
  if (!text.ok()) return text.status();
  double value = 0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
    return OutOfRange(key, *text, "is not a finite number");
  }
  return value;
}

// What is wrong with a layout, or "" when nothing is.
std::string LayoutProblem(const MosaicLayout& l) {
  if (!IsHexId(l.mosaic_id)) return "mosaic_id must be 32 hex digits";
  if (l.width_px < 1 || l.width_px > kMaxSizePx || l.height_px < 1 || l.height_px > kMaxSizePx) {
    return "width and height must be in [1, 2^24] pixels";
  }
  const int t = l.tile_size_px;
  if (t < 16 || t > 4096 || (t & (t - 1)) != 0) {
    return "tile_size must be a power of two in [16, 4096]";
  }
  const int levels = PyramidLevelCount(l.width_px, l.height_px, t);
  if (l.levels != levels) {
    return "levels is " + std::to_string(l.levels) + " but must be " + std::to_string(levels) +
           " for this width, height and tile_size";
  }
  if (!(l.geo.resolution > 0.0) || !std::isfinite(l.geo.resolution)) {
    return "resolution must be a positive number of metres per pixel";
  }
  if (!std::isfinite(l.geo.origin_x) || !std::isfinite(l.geo.origin_y)) {
    return "origin must be finite";
  }
  if (l.version < 0) return "version must be >= 0";
  return "";
}

}  // namespace

Status ValidateLayout(const MosaicLayout& layout) {
  const std::string problem = LayoutProblem(layout);
  return problem.empty() ? Status::Ok() : InvalidInput("mosaic layout: " + problem);
}

Metadata LayoutToMetadata(const MosaicLayout& l, const std::string& created_iso) {
  return {{"format", kMosaicFormat},
          {"mosaic_id", l.mosaic_id},
          {"width", std::to_string(l.width_px)},
          {"height", std::to_string(l.height_px)},
          {"tile_size", std::to_string(l.tile_size_px)},
          {"levels", std::to_string(l.levels)},
          {"resolution", FormatDouble(l.geo.resolution)},
          {"origin_x", FormatDouble(l.geo.origin_x)},
          {"origin_y", FormatDouble(l.geo.origin_y)},
          {"version", std::to_string(l.version)},
          {"created", created_iso}};
}

Result<MosaicLayout> LayoutFromMetadata(const Metadata& metadata) {
  Result<std::string> format = Field(metadata, "format");
  if (!format.ok()) return format.status();
  if (*format != kMosaicFormat) {
    return OutOfRange("format", *format, std::string("is not '") + kMosaicFormat + "'");
  }
  Result<std::string> id = Field(metadata, "mosaic_id");
  if (!id.ok()) return id.status();
  if (!IsHexId(*id)) return OutOfRange("mosaic_id", *id, "is not 32 hex digits");
  if (Result<std::string> created = Field(metadata, "created"); !created.ok()) {
    return created.status();
  }
  const Result<long long> width = IntField(metadata, "width", 1, kMaxSizePx);
  const Result<long long> height = IntField(metadata, "height", 1, kMaxSizePx);
  const Result<long long> tile = IntField(metadata, "tile_size", 16, 4096);
  const Result<long long> levels = IntField(metadata, "levels", 1, 31);
  const Result<double> resolution = FiniteField(metadata, "resolution");
  const Result<double> origin_x = FiniteField(metadata, "origin_x");
  const Result<double> origin_y = FiniteField(metadata, "origin_y");
  const Result<long long> version = IntField(metadata, "version", 0, 1LL << 62);
  for (const Status* s :
       {&width.status(), &height.status(), &tile.status(), &levels.status(), &resolution.status(),
        &origin_x.status(), &origin_y.status(), &version.status()}) {
    if (!s->ok()) return *s;
  }
  MosaicLayout layout;
  layout.mosaic_id = *id;
  layout.width_px = static_cast<int>(*width);
  layout.height_px = static_cast<int>(*height);
  layout.tile_size_px = static_cast<int>(*tile);
  layout.levels = static_cast<int>(*levels);
  layout.geo = {*origin_x, *origin_y, *resolution};
  layout.version = *version;
  if (const std::string problem = LayoutProblem(layout); !problem.empty()) {
    return InvalidInput("metadata inconsistent: " + problem);
  }
  return layout;
}

std::string NewMosaicId() {
  std::random_device device;
  std::mt19937_64 rng((std::uint64_t{device()} << 32) ^ device());
  char buffer[33];
  std::snprintf(buffer, sizeof(buffer), "%016llx%016llx", static_cast<unsigned long long>(rng()),
                static_cast<unsigned long long>(rng()));
  return buffer;
}

std::string IsoTimeNowUtc() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buffer;
}

}  // namespace fleetloc::mosaic
