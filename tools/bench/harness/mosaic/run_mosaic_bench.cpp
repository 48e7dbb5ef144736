// fleetctl bench mosaic: proves the mosaic store scales — for each image size (default 10 Mpx,
// 100 Mpx, 1 Gpx) compose a real-texture floor, import it with the real importer (time, peak RSS)
// and time random tile and block lookups. Progress on stderr; the table and the verdict on stdout;
// every number as JSON with --json.
#include "harness/mosaic/run_mosaic_bench.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "harness/mosaic/bench_mosaic.h"
#include "harness/mosaic/bench_mosaic_report.h"
#include "io/file_util.h"
#include "support/composed_floor.h"
#include "support/floor_images.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

Result<std::vector<cv::Size>> ParseSizes(const std::vector<std::string>& texts) {
  if (texts.empty()) return InvalidInput("--sizes: name at least one WIDTHxHEIGHT");
  std::vector<cv::Size> sizes;
  for (const std::string& text : texts) {
    Result<cv::Size> size = fleetctl::ParsePixelSize(text, "--sizes");
    if (!size.ok()) return size.status();
    sizes.push_back(*size);
  }
  return sizes;
}

Result<std::vector<std::string>> FloorPhotos(const std::string& floors_dir) {
  Result<std::vector<fs::path>> images = fleetctl::ListFloorImages(
      floors_dir.empty() ? fleetctl::DefaultFloorsDir() : fs::path(floors_dir), "--floors-dir");
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

}  // namespace

Status RunMosaicBench(MosaicBenchArgs& args) {
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

}  // namespace fleetloc::bench
