// fleetctl bench tracker-stress: every floor of the stress manifest × frame size × condition, each
// cell a `bench tracker` run (same simulator, scoring and peers); one line per method and cell,
// the cell's verdict against issue 15's targets, tuning and holdout floors in separate tables.
#include "harness/stress/run_stress_bench.h"

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <sstream>

#include "harness/stress/bench_stress.h"
#include "harness/tracker/bench_report.h"
#include "io/file_util.h"
#include "support/parse_numbers.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

// A weak floor: the issue's looser accuracy and time targets apply.
bool PlainClass(const std::string& floor_class) {
  return floor_class == "plain_concrete" || floor_class == "polished_concrete" ||
         floor_class == "epoxy";
}

double Number(const nlohmann::json& summary, const char* group, const char* key) {
  const nlohmann::json& g = group ? summary.value(group, nlohmann::json::object()) : summary;
  return g.contains(key) && g[key].is_number() ? g[key].get<double>() : NAN;
}

void PrintHeader() {
  std::printf("%-18s %-30s %-9s %-6s %-12s %6s %6s %5s %8s %8s %8s %8s\n", "class", "floor", "size",
              "cond", "method", "frames", "lock", "false", "camRMS", "RMS", "ms med", "ms p95");
}

void PrintRow(const StressFloor& floor, const FrameSize& size, const std::string& condition,
              const BenchRow& row) {
  const nlohmann::json& s = row.summary;
  std::printf("%-18s %-30s %-9s %-6s %-12s %6zu %6.3f %5.0f %8.3f %8.3f %8.2f %8.2f\n",
              floor.floor_class.c_str(), floor.file.c_str(), size.label.c_str(), condition.c_str(),
              row.label().c_str(), row.frames(), Number(s, nullptr, "lock_rate"),
              Number(s, "error", "false_locks"), Number(s, "error", "camera_position_rms_px"),
              Number(s, "error", "position_rms_px"), Number(s, "ms_per_frame", "median"),
              Number(s, "ms_per_frame", "p95"));
}

// One cell: the floor scaled for the frame, the condition's run, every method replayed.
Result<nlohmann::json> RunCell(const StressFloor& floor, const FrameSize& size,
                               const std::string& condition, const TrackerStressBenchArgs& args) {
  BenchSettings settings = args.settings;
  settings.width_px = size.width;
  settings.height_px = size.height;
  FLEETLOC_RETURN_IF_ERROR(ApplyStressCondition(condition, &settings));
  const fs::path root = io::AbsoluteDir(args.work_dir);
  Result<fs::path> image = FloorForFrame(floor, size.width, size.height, root / "floors");
  if (!image.ok()) return image.status();
  settings.work_dir = root / size.label / condition;
  spdlog::info("stress: {} {} {}", floor.file, size.label, condition);
  Result<FloorBench> bench = BenchFloor(*image, settings);
  if (!bench.ok()) return bench.status();
  const std::vector<BenchRow> rows = ScoreRows(TableReplays(*bench));
  for (const BenchRow& row : rows) PrintRow(floor, size, condition, row);
  const std::string verdict = JudgeStressCell(rows, floor.floor_class, size);
  std::printf("%-18s %-30s %-9s %-6s -> %s\n", floor.floor_class.c_str(), floor.file.c_str(),
              size.label.c_str(), condition.c_str(), verdict.c_str());
  std::fflush(stdout);
  return nlohmann::json{{"class", floor.floor_class}, {"floor", floor.file},
                        {"split", floor.split},       {"size", size.label},
                        {"condition", condition},     {"methods", RowsJson(rows)},
                        {"verdict", verdict}};
}

}  // namespace

std::string JudgeStressCell(const std::vector<BenchRow>& rows, const std::string& floor_class,
                            const FrameSize& size) {
  const BenchRow* fleetloc = nullptr;
  const BenchRow* on_peer_frames = nullptr;  // "fleetloc@N": when the peers replayed fewer frames
  const BenchRow* ecc = nullptr;
  for (const BenchRow& row : rows) {
    if (row.label() == "fleetloc") fleetloc = &row;
    if (row.label().starts_with("fleetloc@")) on_peer_frames = &row;
    if (row.label() == "ecc") ecc = &row;
  }
  if (!fleetloc) return "n/a";
  const nlohmann::json& f = fleetloc->summary;
  std::vector<std::string> misses;
  if (Number(f, nullptr, "lock_rate") < 0.995) misses.emplace_back("lock");
  if (Number(f, "error", "false_locks") > 0) misses.emplace_back("false lock");
  const double rms = Number(f, "error", "camera_position_rms_px");
  if (!(rms <= (PlainClass(floor_class) ? 0.15 : 0.1))) misses.emplace_back("rms");
  // Against ECC on the same frames: fleetloc's first N when ECC replayed only N. An ECC that
  // locked no frame has no RMS to compare (its summary's error is 0 over no frame).
  const BenchRow* same_frames = on_peer_frames ? on_peer_frames : fleetloc;
  if (ecc && Number(ecc->summary, nullptr, "lock_rate") > 0 &&
      Number(ecc->summary, "error", "camera_position_rms_px") <=
          Number(same_frames->summary, "error", "camera_position_rms_px")) {
    misses.emplace_back("rms vs ecc");
  }
  if (size.width == 640 && size.height == 480) {
    const double median_ms = Number(f, "ms_per_frame", "median");
    if (median_ms > (PlainClass(floor_class) ? 4.0 : 2.0)) misses.emplace_back("time");
    // At least 10× faster than ECC where ECC locked frames, against its median over those frames:
    // an ECC that gives up on a frame within milliseconds (worn asphalt b1 under `fast`: 77 % of
    // the frames, median 2.6 ms over all of them) has not registered it faster.
    if (ecc && Number(ecc->summary, nullptr, "lock_rate") > 0 &&
        Number(ecc->summary, "ms_per_frame", "median_locked") < 10.0 * median_ms) {
      misses.emplace_back("time vs ecc");
    }
  }
  if (misses.empty()) return "PASS";
  std::string text = "MISS:";
  for (const std::string& m : misses) text += " " + m + ",";
  text.pop_back();
  return text;
}

Status RunTrackerStressBench(TrackerStressBenchArgs& args) {
  FLEETLOC_RETURN_IF_ERROR(LoadBenchTrackerOptions(args.tracker_config, &args.settings));
  const fs::path manifest =
      args.manifest.empty() ? DefaultStressManifest() : fs::path(args.manifest);
  Result<std::vector<StressFloor>> floors = ReadStressManifest(manifest);
  if (!floors.ok()) return floors.status();
  std::vector<FrameSize> sizes;
  for (const std::string& text : args.sizes) {
    Result<FrameSize> size = ParseFrameSize(text);
    if (!size.ok()) return size.status();
    sizes.push_back(*size);
  }
  BenchSettings probe = args.settings;
  for (const std::string& c : args.conditions)
    FLEETLOC_RETURN_IF_ERROR(ApplyStressCondition(c, &probe));
  cv::setNumThreads(1);  // every method on one core
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& [split, role] : StressSplits()) {
    if (args.split != "all" && args.split != split) continue;
    std::printf("\n== %s floors (%s)\n", split, role);
    PrintHeader();
    for (const StressFloor& floor : *floors) {
      if (floor.split != split) continue;
      if (!args.classes.empty() && std::find(args.classes.begin(), args.classes.end(),
                                             floor.floor_class) == args.classes.end()) {
        continue;
      }
      for (const FrameSize& size : sizes) {
        for (const std::string& condition : args.conditions) {
          Result<nlohmann::json> cell = RunCell(floor, size, condition, args);
          if (!cell.ok()) return cell.status();
          cells.push_back(std::move(*cell));
        }
      }
    }
  }
  if (args.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(args.json, nlohmann::json{{"cells", cells}}.dump(2) + "\n");
}

}  // namespace fleetloc::bench
