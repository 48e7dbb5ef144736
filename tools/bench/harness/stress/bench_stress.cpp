// Stress-suite pieces: the floors manifest, the camera conditions, floors scaled to the frame.
#include "harness/stress/bench_stress.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "io/file_util.h"
#include "run_io/run.h"
#include "sim/stress_camera.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

constexpr double kFloorOverFrame = 1.6;  // the floor is at least this many frames across

Status BadEntry(const fs::path& manifest, size_t index, const std::string& why) {
  return InvalidInput(manifest.string() + ": entry " + std::to_string(index) + ": " + why);
}

Result<StressFloor> ParseEntry(const nlohmann::json& entry, const fs::path& manifest,
                               size_t index) {
  if (!entry.is_object()) return BadEntry(manifest, index, "must be an object");
  for (const char* key : {"file", "class", "split"}) {
    if (!entry.contains(key) || !entry[key].is_string() || entry[key].get<std::string>().empty()) {
      return BadEntry(manifest, index, std::string("'") + key + "' must be a non-empty string");
    }
  }
  StressFloor floor;
  floor.file = entry["file"].get<std::string>();
  floor.floor_class = entry["class"].get<std::string>();
  floor.split = entry["split"].get<std::string>();
  if (!IsStressSplit(floor.split)) {
    return BadEntry(manifest, index, R"('split' must be "tuning", "holdout" or "fresh")");
  }
  if (fs::path(floor.file).filename() != fs::path(floor.file)) {
    return BadEntry(manifest, index, "'file' must name a file beside the manifest");
  }
  floor.image = manifest.parent_path() / floor.file;
  std::error_code ec;
  if (!fs::is_regular_file(floor.image, ec)) {
    return BadEntry(manifest, index, floor.image.string() + " not found");
  }
  return floor;
}

}  // namespace

Result<std::vector<StressFloor>> ReadStressManifest(const fs::path& manifest) {
  Result<std::string> text = io::ReadFileText(manifest);
  if (!text.ok()) return text.status();
  const nlohmann::json json = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_array() || json.empty()) {
    return InvalidInput(manifest.string() + ": must be a non-empty JSON array of floors");
  }
  std::vector<StressFloor> floors;
  for (size_t i = 0; i < json.size(); ++i) {
    Result<StressFloor> floor = ParseEntry(json[i], manifest, i);
    if (!floor.ok()) return floor.status();
    floors.push_back(std::move(*floor));
  }
  return floors;
}

Result<FrameSize> ParseFrameSize(const std::string& text) {
  FrameSize size{0, 0, text};
  char x = 0;
  std::istringstream in(text);
  if (!(in >> size.width >> x >> size.height) || x != 'x' || !in.eof() || size.width < 64 ||
      size.height < 64 || size.width > 4096 || size.height > 4096) {
    return InvalidInput("--sizes: '" + text + "' is not WIDTHxHEIGHT within 64..4096");
  }
  return size;
}

fs::path DefaultStressManifest() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  fs::path beside =
      exe.parent_path().parent_path().parent_path() / "data/stress_floors/floors.json";
  if (!ec && fs::is_regular_file(beside, ec)) return beside;
  return fs::path(FLEETLOC_SOURCE_DIR) / "data/stress_floors/floors.json";
}

const std::vector<StressSplit>& StressSplits() {
  static const std::vector<StressSplit> kSplits{
      {"tuning", "used while tuning"},
      {"holdout", "never used while tuning"},
      {"fresh", "another source's photographs, never looked at before their first run"}};
  return kSplits;
}

bool IsStressSplit(const std::string& split) {
  return std::any_of(StressSplits().begin(), StressSplits().end(),
                     [&](const StressSplit& s) { return split == s.name; });
}

const std::vector<std::string>& StressConditionNames() {
  static const std::vector<std::string> kNames{"clean", "fast", "dusty", "all", "marks", "camera"};
  return kNames;
}

Status ApplyStressCondition(const std::string& name, BenchSettings* s) {
  const std::optional<sim::RenderOptions> effects = sim::StressCameraEffects(name);
  if (!effects) {
    return InvalidInput("--conditions: unknown condition '" + name +
                        "' (known: clean, fast, dusty, all, marks, camera, aisles)");
  }
  const bool fast = sim::StressConditionIsFast(name), other_camera = name == "camera";
  // Frames 1/3 of a width apart, 0.6 widths (another camera), or 1.25 widths (no overlap in any
  // direction of travel).
  s->speed_px_s = s->rate_hz * s->width_px * (fast ? 1.25 : other_camera ? 0.6 : 1.0 / 3.0);
  s->render = *effects;
  s->route = sim::StressConditionRoute(name);
  // A short exposure: the floor moves about 1 px during it; another camera's about 4 px.
  s->render.exposure_s = fast ? 1.0 / s->speed_px_s : other_camera ? 4.0 / s->speed_px_s : 0.0;
  return Status::Ok();
}

Result<fs::path> FloorForFrame(const StressFloor& floor, int width_px, int height_px,
                               const fs::path& dir) {
  Result<cv::Mat> image = run_io::ReadGrayImage(floor.image);
  if (!image.ok()) return image.status();
  const double need =
      std::max(kFloorOverFrame * width_px / image->cols, kFloorOverFrame * height_px / image->rows);
  const int factor = std::max(1, static_cast<int>(std::ceil(need - 1e-9)));
  if (factor == 1) return floor.image;
  const fs::path scaled =
      dir / (fs::path(floor.file).stem().string() + "_x" + std::to_string(factor) + ".png");
  std::error_code ec;
  if (fs::is_regular_file(scaled, ec)) return scaled;
  fs::create_directories(dir, ec);
  cv::Mat up;
  cv::resize(*image, up, {}, factor, factor, cv::INTER_CUBIC);
  const fs::path partial = scaled.string() + ".partial.png";
  if (!cv::imwrite(partial.string(), up)) return Internal(partial.string() + ": cannot write");
  fs::rename(partial, scaled, ec);
  if (ec) return Internal(scaled.string() + ": " + ec.message());
  return scaled;
}

}  // namespace fleetloc::bench
