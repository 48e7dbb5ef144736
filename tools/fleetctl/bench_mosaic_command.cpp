// fleetctl bench mosaic: proves the mosaic store scales — for each image size (default 10 Mpx,
// 100 Mpx, 1 Gpx) compose a real-texture floor, import it with the real importer (time, peak RSS)
// and time random tile and block lookups. Progress on stderr; the table and the verdict on stdout;
// every number as JSON with --json.
#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "bench_mosaic.h"
#include "bench_mosaic_report.h"
#include "commands.h"
#include "composed_floor.h"
#include "floor_images.h"
#include "io/file_util.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

struct BenchMosaicArgs {
  std::vector<std::string> sizes{"3200x3200", "10240x10240", "32768x32768"};
  std::string floors_dir;
  std::string work_dir = (fs::temp_directory_path() / "fleetloc-bench-mosaic").string();
  std::string json;
  MosaicBenchSettings settings;
};

Result<std::vector<cv::Size>> ParseSizes(const std::vector<std::string>& texts) {
  if (texts.empty()) return InvalidInput("--sizes: name at least one WIDTHxHEIGHT");
  std::vector<cv::Size> sizes;
  for (const std::string& text : texts) {
    Result<cv::Size> size = ParsePixelSize(text, "--sizes");
    if (!size.ok()) return size.status();
    sizes.push_back(*size);
  }
  return sizes;
}

Result<std::vector<std::string>> FloorPhotos(const std::string& floors_dir) {
  Result<std::vector<fs::path>> images = ListFloorImages(
      floors_dir.empty() ? DefaultFloorsDir() : fs::path(floors_dir), "--floors-dir");
  if (!images.ok()) return images.status();
  std::vector<std::string> photos;
  for (const fs::path& image : *images) photos.push_back(image.string());
  return photos;
}

nlohmann::json SettingsJson(const MosaicBenchSettings& s) {
  return {{"photos", s.photos},
          {"work_dir", s.work_dir.string()},
          {"block_px", s.block_px},
          {"seed", s.seed},
          {"resolution_m", s.resolution_m},
          {"tile_samples", s.lookups.tile_samples},
          {"block_samples", s.lookups.block_samples},
          {"lookup_block_px", {s.lookups.block_px.width, s.lookups.block_px.height}},
          {"tile_cache_bytes", s.lookups.cache_bytes},
          {"threads", 1}};
}

Status RunBenchMosaic(BenchMosaicArgs& args) {
  Result<std::vector<cv::Size>> sizes = ParseSizes(args.sizes);
  if (!sizes.ok()) return sizes.status();
  Result<std::vector<std::string>> photos = FloorPhotos(args.floors_dir);
  if (!photos.ok()) return photos.status();
  args.settings.photos = *photos;
  args.settings.work_dir = io::AbsoluteDir(args.work_dir);
  args.settings.lookups.seed = args.settings.seed;
  cv::setNumThreads(1);  // one core; and no worker threads may exist when the steps fork
  std::vector<MosaicSizeBench> results;
  nlohmann::json json{{"settings", SettingsJson(args.settings)},
                      {"sizes", nlohmann::json::array()}};
  for (const cv::Size& size : *sizes) {
    Result<MosaicSizeBench> bench = BenchMosaicSize(size, args.settings);
    if (!bench.ok()) return bench.status();
    json["sizes"].push_back(MosaicSizeJson(*bench));
    results.push_back(*bench);
  }
  std::cout << "\n== mosaic store at scale: real-texture floors from " << photos->size()
            << " photos, tile size 256, one core\n";
  PrintMosaicTable(std::cout, results);
  const ScalingVerdict verdict = JudgeScaling(results);
  PrintScalingVerdict(std::cout, verdict);
  json["verdict"] = ScalingVerdictJson(verdict);
  if (args.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(args.json, json.dump(2) + "\n");
}

}  // namespace

void AddBenchMosaicCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<BenchMosaicArgs>();
  MosaicBenchSettings& s = args->settings;
  CLI::App* cmd = bench.add_subcommand(
      "mosaic", "Mosaic store at scale: import time and peak RSS, tile and block lookup latency");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--sizes", args->sizes, "Image sizes WIDTHxHEIGHT, comma-separated")
      ->delimiter(',');
  cmd->add_option("--floors-dir", args->floors_dir,
                  "Floor photos to compose from (default: the source tree's " +
                      std::string(kFloorsSubdir) + ")");
  cmd->add_option("--work-dir", args->work_dir, "Composed floors and mosaics, one dir per size");
  cmd->add_option("--json", args->json, "Write every number to this JSON file");
  cmd->add_option("--block", s.block_px, "Composition block side, px")->check(CLI::Range(16, 4096));
  cmd->add_option("--seed", s.seed, "Composition and sampling seed");
  cmd->add_option("--tile-samples", s.lookups.tile_samples, "Random tiles read, each way")
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--block-samples", s.lookups.block_samples, "Random blocks read cold and warm")
      ->check(CLI::Range(1, 10000000));
  cmd->add_flag("--keep-files", s.keep_files, "Keep each size's PGM and mosaic");
  cmd->callback([args, result] { *result = RunBenchMosaic(*args); });
}

}  // namespace fleetloc::fleetctl
