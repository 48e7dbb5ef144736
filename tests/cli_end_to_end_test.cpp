// End to end through the fleetctl command line (CONTRACT §6): a real floor photo imported as a
// mosaic, a simulated run over it, the tracker replayed over the run, and the tracker benchmark.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace fleetloc::testing {
namespace {

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

}  // namespace
}  // namespace fleetloc::testing
