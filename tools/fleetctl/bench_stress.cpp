// Stress-suite pieces: the floors manifest, the camera conditions, floors scaled to the frame.
#include "bench_stress.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "io/file_util.h"
#include "io/run.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

constexpr double kFloorOverFrame = 1.6;  // the floor is at least this many frames across

Status BadEntry(const fs::path& manifest, size_t index, const std::string& why) {
  return InvalidInput(manifest.string() + ": entry " + std::to_string(index) + ": " + why);
}

Result<StressFloor> ParseEntry(const nlohmann::json& entry, const fs::path& manifest,
                               size_t index) {
  static const std::set<std::string> kSplits{"tuning", "holdout"};
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
  if (!kSplits.count(floor.split)) {
    return BadEntry(manifest, index, "'split' must be \"tuning\" or \"holdout\"");
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
  const fs::path beside =
      exe.parent_path().parent_path().parent_path() / "data/stress_floors/floors.json";
  if (!ec && fs::is_regular_file(beside, ec)) return beside;
  return fs::path(FLEETLOC_SOURCE_DIR) / "data/stress_floors/floors.json";
}

const std::vector<std::string>& StressConditionNames() {
  static const std::vector<std::string> kNames{"clean", "fast", "dusty", "all", "marks"};
  return kNames;
}

namespace {

// Occluders of other shapes than the dust the tracker was tuned under (held out: never used while
// tuning): tyre marks, hard-edged debris and the vehicle's own shadow, with milder vignetting and
// light than "dusty".
void ApplyMarksCondition(BenchSettings* s) {
  s->speed_px_s = s->rate_hz * s->width_px / 3.0;
  sim::RenderOptions r;
  r.dust_fraction = 0.0;
  r.tyre_mark_fraction = 0.12;
  r.debris_fraction = 0.05;
  r.shadow_fraction = 0.3;
  r.shadow_depth = 0.6;
  r.vignetting_corner_loss = 0.3;
  r.lighting_amplitude = 0.2;
  r.gain_min = 0.8;
  r.gain_max = 1.2;
  s->render = r;
}

}  // namespace

Status ApplyStressCondition(const std::string& name, BenchSettings* s) {
  const auto& names = StressConditionNames();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    return InvalidInput("--conditions: unknown condition '" + name +
                        "' (known: clean, fast, dusty, all, marks)");
  }
  if (name == "marks") {
    ApplyMarksCondition(s);
    return Status::Ok();
  }
  const bool fast = name == "fast" || name == "all";
  const bool dusty = name == "dusty" || name == "all";
  // Frames 1/3 of a width apart, or 1.25 widths (no overlap in any direction of travel).
  s->speed_px_s = s->rate_hz * s->width_px * (fast ? 1.25 : 1.0 / 3.0);
  sim::RenderOptions r;  // `fleetctl sim`'s defaults, then the condition
  r.dust_fraction = dusty ? 0.3 : 0.0;
  r.dust_max_radius_px = dusty ? 40.0 : r.dust_max_radius_px;
  r.dust_streak_fraction = dusty ? 0.5 : r.dust_streak_fraction;
  r.dust_max_opacity = dusty ? 0.9 : r.dust_max_opacity;
  r.vignetting_corner_loss = dusty ? 0.5 : 0.05;
  r.lighting_amplitude = dusty ? 0.4 : 0.03;
  r.blur_sigma_px = dusty ? 1.5 : 0.5;
  const bool jitter = fast || dusty;
  r.gain_min = jitter ? 0.75 : 0.97;
  r.gain_max = jitter ? 1.25 : 1.03;
  r.bias_min_dn = dusty ? -20.0 : -2.0;
  r.bias_max_dn = dusty ? 20.0 : 2.0;
  r.noise_sigma_dn = fast ? 4.0 : 1.0;
  r.shot_noise_dn = fast ? 0.3 : 0.05;
  // A short exposure: the floor moves about 1 px during it.
  r.exposure_s = fast ? 1.0 / s->speed_px_s : 0.0;
  s->render = r;
  return Status::Ok();
}

Result<fs::path> FloorForFrame(const StressFloor& floor, int width_px, int height_px,
                               const fs::path& dir) {
  Result<cv::Mat> image = io::ReadGrayImage(floor.image);
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

}  // namespace fleetloc::fleetctl
