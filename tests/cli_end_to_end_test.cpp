// End to end through the fleetctl command line (docs/cli.md): a real floor photo imported as a
// mosaic, a simulated run over it, the tracker replayed over the run, the tracker benchmark, a
// floor composed from blocks of the photos and the mosaic store benchmark.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace fleetloc::testing {
namespace {

namespace fs = std::filesystem;

const std::string kFloor = FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png";
const std::string kPosesHeader = "t,x,y,theta,sxx,sxy,sxt,syy,syt,stt,status,inliers";

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(CliEndToEnd, SimulatedRunOverImportedPhotoTracksToATenthOfAPixel) {
  const ScratchDir dir("cli_e2e");
  const std::string mosaic = dir / "floor.db", run = dir / "run", poses = dir / "poses.csv";
  const CommandResult imported =
      RunFleetctl("mosaic import " + Quote(kFloor) + " --resolution 0.0005 --out " + Quote(mosaic));
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const CommandResult simulated = RunFleetctl("sim --mosaic " + Quote(mosaic) + " --out " +
                                              Quote(run) + " --frames 60 --seed 3");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;

  const CommandResult tracked = RunFleetctl("track --mosaic " + Quote(mosaic) + " --run " +
                                            Quote(run) + " --out " + Quote(poses));
  ASSERT_EQ(tracked.exit_code, 0) << tracked.err;
  const nlohmann::json summary = nlohmann::json::parse(tracked.out);
  EXPECT_EQ(summary["frames"], 60);
  EXPECT_GE(summary["lock_rate"].get<double>(), 0.95);
  EXPECT_LT(summary["error"]["camera_position_rms_px"].get<double>(), 0.1);
  // The time over the frames tracked: every frame here, so within the spread of all frames.
  const nlohmann::json& ms = summary["ms_per_frame"];
  EXPECT_GT(ms["median_locked"].get<double>(), 0.0);
  EXPECT_LE(ms["median_locked"].get<double>(), ms["p95"].get<double>());

  const std::vector<std::string> lines = Lines(ReadWhole(poses));
  ASSERT_EQ(lines.size(), 61u);
  EXPECT_EQ(lines[0], kPosesHeader);
}

TEST(CliEndToEnd, BenchTrackerReportsFleetlocAgainstAPeer) {
  const ScratchDir dir("cli_bench");
  const CommandResult bench =
      RunFleetctl("bench tracker --floors " + Quote(kFloor) +
                  " --frames 20 --methods fleetloc,phase --work-dir " + Quote(dir / "work") +
                  " --json " + Quote(dir / "bench.json"));
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  EXPECT_NE(bench.out.find("fleetloc "), std::string::npos) << bench.out;
  EXPECT_NE(bench.out.find("phase "), std::string::npos) << bench.out;
  EXPECT_NE(bench.out.find("verdict rock_dirt_2048.png"), std::string::npos) << bench.out;

  const nlohmann::json json = nlohmann::json::parse(ReadWhole(dir / "bench.json"));
  ASSERT_EQ(json["floors"].size(), 1u);
  const nlohmann::json& fleetloc = json["floors"][0]["methods"]["fleetloc"];
  EXPECT_EQ(fleetloc["frames"], 20);
  EXPECT_GE(fleetloc["lock_rate"].get<double>(), 0.95);
  EXPECT_TRUE(json["floors"][0]["verdict"]["applicable"].get<bool>());
  EXPECT_GT(json["peak_rss_bytes"].get<long long>(), 0);
}

TEST(CliEndToEnd, BenchAgentComparesTheLiveAgentWithTheOfflineTracker) {
  ScratchDir dir("cli_bench_agent");
  const std::string json = dir / "agent.json";
  const CommandResult r = RunFleetctl("bench agent --frames 20 --domain 93 --work-dir " +
                                      Quote(dir / "work") + " --json " + Quote(json));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("live / offline median"), std::string::npos) << r.out;
  std::ifstream in(json);
  const auto report = nlohmann::json::parse(in);
  EXPECT_EQ(report["live"]["frames"], 20);
  EXPECT_GT(report["offline"]["median_ms"].get<double>(), 0.0);
  EXPECT_GT(report["ratio"].get<double>(), 0.0);
  EXPECT_EQ(report["live"]["tiles"]["timeouts"], 0);
}

TEST(CliEndToEnd, ComposeFloorOfASizeIsTheSamePgmEveryTimeForASeed) {
  const ScratchDir dir("cli_compose");
  const std::string photos =
      Quote(kFloor) + " " + Quote(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/gravel_1024.png");
  const auto compose = [&](const std::string& out, int seed) {
    return RunFleetctl("compose-floor " + photos + " --size 1100x700 --block 256 --seed " +
                       std::to_string(seed) + " --out " + Quote(out));
  };
  ASSERT_EQ(compose(dir / "a.pgm", 5).exit_code, 0);
  ASSERT_EQ(compose(dir / "b.pgm", 5).exit_code, 0);
  ASSERT_EQ(compose(dir / "c.pgm", 6).exit_code, 0);
  const std::string a = ReadWhole(dir / "a.pgm");
  const std::string header = "P5\n1100 700\n255\n";
  ASSERT_EQ(a.size(), header.size() + 1100 * 700);
  EXPECT_EQ(a.substr(0, header.size()), header);
  EXPECT_EQ(a, ReadWhole(dir / "b.pgm"));
  EXPECT_NE(a, ReadWhole(dir / "c.pgm"));
}

TEST(CliEndToEnd, BenchMosaicReportsImportAndLookupsForEachSize) {
  const ScratchDir dir("cli_bench_mosaic");
  const CommandResult bench = RunFleetctl(
      "bench mosaic --sizes 600x400,1100x700 --tile-samples 50 --block-samples 10 --work-dir " +
      Quote(dir / "work") + " --json " + Quote(dir / "bench.json"));
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  EXPECT_NE(bench.out.find("1100x700"), std::string::npos) << bench.out;
  EXPECT_NE(bench.out.find("verdict: import peak RSS"), std::string::npos) << bench.out;

  const nlohmann::json json = nlohmann::json::parse(ReadWhole(dir / "bench.json"));
  ASSERT_EQ(json["sizes"].size(), 2u);
  const nlohmann::json& large = json["sizes"][1];
  EXPECT_EQ(large["size_px"], nlohmann::json({1100, 700}));
  EXPECT_NEAR(large["megapixels"].get<double>(), 0.77, 1e-9);
  EXPECT_GT(large["import"]["wall_s"].get<double>(), 0.0);
  EXPECT_GT(large["import"]["peak_rss_bytes"].get<long long>(), 1 << 20);
  EXPECT_EQ(large["pgm_bytes"].get<std::size_t>(),
            std::string("P5\n1100 700\n255\n").size() + 1100 * 700);
  EXPECT_GT(large["mosaic_bytes"].get<long long>(), 100000);
  const nlohmann::json& lookup = large["lookup"];
  EXPECT_EQ(lookup["levels"], 4);
  EXPECT_EQ(lookup["tiles"], 15 + 6 + 2 + 1);  // 5x3, 3x2, 2x1 and 1x1 tiles
  EXPECT_EQ(lookup["missing_tiles"], 0);
  EXPECT_NE(lookup["query_plan"].get<std::string>().find("USING INDEX"), std::string::npos);
  for (const char* op : {"tile_bytes", "tile_decoded", "block_cold", "block_warm"}) {
    EXPECT_GT(lookup[op]["p50_us"].get<double>(), 0.0) << op;
    EXPECT_GE(lookup[op]["p99_us"].get<double>(), lookup[op]["p50_us"].get<double>()) << op;
  }
  EXPECT_EQ(lookup["tile_bytes"]["samples"], 50);
  EXPECT_EQ(lookup["block_cold"]["samples"], 10);
  EXPECT_TRUE(json["verdict"]["applicable"].get<bool>());
  EXPECT_GT(json["verdict"]["import_rss_ratio"].get<double>(), 0.0);
  EXPECT_FALSE(
      fs::exists(dir.path() / "work" / "1100x700" / "floor.pgm"));  // removed once measured
}

}  // namespace
}  // namespace fleetloc::testing
