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
  int tile_samples = 2000;  // in all rounds
  int block_samples = 300;  // in all rounds
  int rounds = 5;
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

// Every size composed and imported, then the lookup rounds taking the sizes in turn, so a change
// of host speed (other tenants) during the run hits every size alike.
Result<std::vector<MosaicSizeBench>> BenchAllSizes(const std::vector<cv::Size>& sizes, int rounds,
                                                   const MosaicBenchSettings& settings) {
  std::vector<MosaicSizeBench> benches;
  for (const cv::Size& size : sizes) {
    Result<MosaicSizeBench> bench = ComposeAndImport(size, settings);
    if (!bench.ok()) return bench.status();
    benches.push_back(std::move(bench).value());
  }
  for (int round = 0; round < rounds; ++round) {
    for (MosaicSizeBench& bench : benches) {
      FLEETLOC_RETURN_IF_ERROR(AddLookupRound(settings, round, &bench));
    }
  }
  for (const MosaicSizeBench& bench : benches) RemoveSizeFiles(settings, bench);
  return benches;
}

nlohmann::json SettingsJson(const MosaicBenchSettings& s, int rounds) {
  return {{"photos", s.photos},
          {"work_dir", s.work_dir.string()},
          {"block_px", s.block_px},
          {"seed", s.seed},
          {"resolution_m", s.resolution_m},
          {"tile_samples_per_round", s.lookups.tile_samples},
          {"block_samples_per_round", s.lookups.block_samples},
          {"lookup_block_px", {s.lookups.block_px.width, s.lookups.block_px.height}},
          {"tile_cache_bytes", s.lookups.cache_bytes},
          {"lookup_rounds", rounds},
          {"threads", 1}};
}

Status RunBenchMosaic(BenchMosaicArgs& args) {
  Result<std::vector<cv::Size>> sizes = ParseSizes(args.sizes);
  if (!sizes.ok()) return sizes.status();
  Result<std::vector<std::string>> photos = FloorPhotos(args.floors_dir);
  if (!photos.ok()) return photos.status();
  args.settings.photos = *photos;
  args.settings.work_dir = io::AbsoluteDir(args.work_dir);
  const auto per_round = [&](int total) { return (total + args.rounds - 1) / args.rounds; };
  args.settings.lookups.tile_samples = per_round(args.tile_samples);
  args.settings.lookups.block_samples = per_round(args.block_samples);
  cv::setNumThreads(1);  // one core; and no worker threads may exist when the steps fork
  Result<std::vector<MosaicSizeBench>> benched = BenchAllSizes(*sizes, args.rounds, args.settings);
  if (!benched.ok()) return benched.status();
  const std::vector<MosaicSizeBench>& results = *benched;
  nlohmann::json json{{"settings", SettingsJson(args.settings, args.rounds)},
                      {"sizes", nlohmann::json::array()}};
  for (const MosaicSizeBench& bench : results) json["sizes"].push_back(MosaicSizeJson(bench));
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
  cmd->add_option("--tile-samples", args->tile_samples, "Random tiles read, each way, per size")
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--block-samples", args->block_samples,
                  "Random blocks read cold and warm, per size")
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--rounds", args->rounds,
                  "Lookup rounds taking the sizes in turn (samples split between rounds)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("--keep-files", s.keep_files, "Keep each size's PGM and mosaic");
  cmd->callback([args, result] { *result = RunBenchMosaic(*args); });
}

}  // namespace fleetloc::fleetctl
