// Relocalization on the stress floors (see bench_reloc_stress.h): cells, their table, the summary.
#include "harness/reloc/bench_reloc_stress.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "harness/stress/bench_stress.h"
#include "harness/tracker/bench_tracker.h"
#include "io/file_util.h"
#include "mosaic/mosaic_view.h"
#include "run_io/run.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

constexpr double kResolutionM = 0.0005;  // the stress suite's floors

// The floor image of a layout: the scaled floor itself, or it twice side by side (written to
// `dir`, never next to a floor photo of the source tree).
Result<fs::path> LayoutImage(const fs::path& scaled, const std::string& layout,
                             const fs::path& dir) {
  if (layout == "single") return scaled;
  const fs::path twice = dir / (scaled.stem().string() + "_twice.png");
  std::error_code ec;
  if (fs::is_regular_file(twice, ec)) return twice;
  fs::create_directories(dir, ec);
  Result<cv::Mat> image = run_io::ReadGrayImage(scaled);
  if (!image.ok()) return image.status();
  cv::Mat both;
  cv::hconcat(*image, *image, both);
  const fs::path partial = twice.string() + ".partial.png";
  if (!cv::imwrite(partial.string(), both)) return Internal(partial.string() + ": cannot write");
  fs::rename(partial, twice, ec);
  if (ec) return Internal(twice.string() + ": " + ec.message());
  return twice;
}

// The trial settings of a cell: its frame size, the condition's camera effects and frame spacing.
Result<RelocTrialSettings> CellSettings(const RelocStressArgs& args, const FrameSize& size,
                                        const std::string& condition) {
  BenchSettings bench;
  bench.width_px = size.width;
  bench.height_px = size.height;
  FLEETLOC_RETURN_IF_ERROR(ApplyStressCondition(condition, &bench));
  RelocTrialSettings s = args.trials;
  s.width_px = size.width;
  s.height_px = size.height;
  s.render = bench.render;
  s.frame_period_s = 1.0 / bench.rate_hz;
  s.step_m = bench.speed_px_s / bench.rate_hz * kResolutionM;
  return s;
}

struct Cell {
  const StressFloor* floor = nullptr;
  FrameSize size;
  std::string condition, layout;
};

// The index of a cell's mosaic, built in this process: its numbers as JSON.
nlohmann::json IndexJson(const relocalization::PlaceIndex& index, double seconds,
                         const mosaic::MosaicLayout& layout) {
  const double mpx = layout.width_px * static_cast<double>(layout.height_px) / 1e6;
  return {{"features", index.size()},
          {"memory_bytes", index.MemoryBytes()},
          {"memory_bytes_per_mpx", index.MemoryBytes() / mpx},
          {"build_s", seconds},
          {"build_s_per_mpx", seconds / mpx},
          {"megapixels", mpx}};
}

// "in 1 s/wrong" of the single-frame outcome, when the trials combined frames ("-" otherwise).
std::string SingleFrame(const nlohmann::json& t) {
  if (!t.contains("single_frame")) return "-";
  const nlohmann::json& s = t["single_frame"];
  return std::to_string(s["correct_within_target"].get<int>()) + "/" +
         std::to_string(s["wrong_pose"].get<int>());
}

void PrintRow(const Cell& cell, const nlohmann::json& t, const nlohmann::json& index) {
  std::printf("%-18s %-30s %-9s %-6s %-8s %6d %7d %7d %6d %6d %4d %8.0f %8.0f %8.0f %9s\n",
              cell.floor->floor_class.c_str(), cell.floor->file.c_str(), cell.size.label.c_str(),
              cell.condition.c_str(), cell.layout.c_str(), t["trials"].get<int>(),
              t["correct"].get<int>(), t["correct_within_target"].get<int>(),
              t["wrong_pose"].get<int>(), t["not_found"].get<int>(),
              t["not_found_at_repeated_place"].get<int>(), t["attempt_ms"]["p95"].get<double>(),
              t["time_to_correct_pose_ms"]["p95"].get<double>(), index["features"].get<double>(),
              SingleFrame(t).c_str());
  std::fflush(stdout);
}

void PrintHeader() {
  std::printf("%-18s %-30s %-9s %-6s %-8s %6s %7s %7s %6s %6s %4s %8s %8s %8s %9s\n", "class",
              "floor", "size", "cond", "layout", "trials", "correct", "in 1 s", "wrong", "none",
              "rep", "try p95", "pose p95", "features", "1f 1s/wr");
}

Result<nlohmann::json> RunCell(const Cell& cell, const RelocStressArgs& args) {
  const fs::path root = io::AbsoluteDir(args.work_dir);
  Result<fs::path> scaled =
      FloorForFrame(*cell.floor, cell.size.width, cell.size.height, root / "floors");
  if (!scaled.ok()) return scaled.status();
  Result<fs::path> image = LayoutImage(*scaled, cell.layout, root / "floors");
  if (!image.ok()) return image.status();
  Result<std::shared_ptr<mosaic::TileStore>> store =
      OpenFloorMosaic(*image, kResolutionM, root / "mosaics" / image->stem());
  if (!store.ok()) return store.status();
  const mosaic::MosaicLayout layout = (*store)->layout();
  mosaic::MosaicView view(layout, mosaic::MakeTileLoader(*store),
                          std::make_shared<mosaic::TileCache>(64LL << 20));
  const auto start = std::chrono::steady_clock::now();
  Result<relocalization::PlaceIndex> index = relocalization::PlaceIndex::Build(view, args.index);
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Result<RelocTrialSettings> settings = CellSettings(args, cell.size, cell.condition);
  if (!settings.ok()) return settings.status();
  spdlog::info("reloc stress: {} {} {} {}", cell.floor->file, cell.size.label, cell.condition,
               cell.layout);
  // A floor without any feature has no index: the dense search alone.
  Result<std::vector<RelocTrial>> trials =
      RunRelocTrials(*store, index.ok() ? &*index : nullptr, *settings);
  if (!trials.ok()) return trials.status();
  const nlohmann::json stats = RelocTrialStats(*trials, *settings);
  const nlohmann::json index_json =
      index.ok() ? IndexJson(*index, build_s, layout)
                 : nlohmann::json{{"features", 0}, {"error", index.status().message()}};
  PrintRow(cell, stats, index_json);
  return nlohmann::json{{"class", cell.floor->floor_class},
                        {"floor", cell.floor->file},
                        {"split", cell.floor->split},
                        {"size", cell.size.label},
                        {"condition", cell.condition},
                        {"layout", cell.layout},
                        {"index", index_json},
                        {"trials", stats}};
}

// Per split, class, condition and layout: trials, correct within 1 s, wrong, not found, the
// slowest cell's attempt p95.
void PrintSummary(const nlohmann::json& cells, const std::string& split) {
  struct Sum {
    int trials = 0, within = 0, wrong = 0, none = 0, repeated = 0, single_within = 0,
        single_wrong = 0;
    double attempt_p95_ms = 0;
  };
  std::map<std::string, Sum> sums;
  for (const nlohmann::json& c : cells) {
    if (c["split"] != split) continue;
    Sum& s = sums[c["class"].get<std::string>() + " " + c["condition"].get<std::string>() + " " +
                  c["layout"].get<std::string>()];
    const nlohmann::json& t = c["trials"];
    s.trials += t["trials"].get<int>();
    s.within += t["correct_within_target"].get<int>();
    s.wrong += t["wrong_pose"].get<int>();
    s.none += t["not_found"].get<int>();
    s.repeated += t["not_found_at_repeated_place"].get<int>();
    if (t.contains("single_frame")) {
      s.single_within += t["single_frame"]["correct_within_target"].get<int>();
      s.single_wrong += t["single_frame"]["wrong_pose"].get<int>();
    }
    s.attempt_p95_ms = std::max(s.attempt_p95_ms, t["attempt_ms"]["p95"].get<double>());
  }
  std::printf(
      "\n-- %s summary: class condition layout: correct within 1 s / trials, wrong, none (of "
      "those at places the floor repeats), correct within 1 s of the trials elsewhere, worst "
      "cell's attempt p95 ms; single frame: correct within 1 s, wrong\n",
      split.c_str());
  for (const auto& [key, s] : sums) {
    const int elsewhere = s.trials - s.repeated;
    char share[16] = "    -  ";
    if (elsewhere > 0) std::snprintf(share, sizeof share, "%5.1f %%", 100.0 * s.within / elsewhere);
    std::printf("%-40s %5d/%-5d (%5.1f %%) wrong %d none %d (%d)  %s  %6.0f ms  1f %d wrong %d\n",
                key.c_str(), s.within, s.trials, 100.0 * s.within / s.trials, s.wrong, s.none,
                s.repeated, share, s.attempt_p95_ms, s.single_within, s.single_wrong);
  }
}

bool Selected(const StressFloor& floor, const RelocStressArgs& args, const std::string& split) {
  if (floor.split != split) return false;
  return args.classes.empty() || std::find(args.classes.begin(), args.classes.end(),
                                           floor.floor_class) != args.classes.end();
}

Status CheckArgs(const RelocStressArgs& args, std::vector<FrameSize>* sizes) {
  for (const std::string& text : args.sizes) {
    Result<FrameSize> size = ParseFrameSize(text);
    if (!size.ok()) return size.status();
    sizes->push_back(*size);
  }
  BenchSettings probe;
  for (const std::string& c : args.conditions)
    FLEETLOC_RETURN_IF_ERROR(ApplyStressCondition(c, &probe));
  for (const std::string& l : args.layouts) {
    if (l != "single" && l != "repeated")
      return InvalidInput("--layouts: unknown layout '" + l + "' (known: single, repeated)");
  }
  return Status::Ok();
}

}  // namespace

Status RunRelocStress(const RelocStressArgs& args) {
  const fs::path manifest =
      args.manifest.empty() ? DefaultStressManifest() : fs::path(args.manifest);
  Result<std::vector<StressFloor>> floors = ReadStressManifest(manifest);
  if (!floors.ok()) return floors.status();
  std::vector<FrameSize> sizes;
  FLEETLOC_RETURN_IF_ERROR(CheckArgs(args, &sizes));
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& [name, role] : StressSplits()) {
    const std::string split = name;
    if (args.split != "all" && args.split != split) continue;
    std::printf("\n== %s floors (%s)\n", name, role);
    PrintHeader();
    for (const StressFloor& floor : *floors) {
      if (!Selected(floor, args, split)) continue;
      for (const FrameSize& size : sizes) {
        for (const std::string& condition : args.conditions) {
          for (const std::string& layout : args.layouts) {
            Result<nlohmann::json> cell = RunCell({&floor, size, condition, layout}, args);
            if (!cell.ok()) return cell.status();
            cells.push_back(std::move(*cell));
          }
        }
      }
    }
    PrintSummary(cells, split);
  }
  if (args.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(args.json, nlohmann::json{{"cells", cells}}.dump(2) + "\n");
}

}  // namespace fleetloc::bench
