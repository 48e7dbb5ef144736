// fleetctl reloc through the command line: a real floor photo imported as a mosaic, a simulated
// run over it, frames relocalized with no prior (the place index built once, then loaded from the
// mosaic's cache table), and bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace fleetloc::testing {
namespace {

const std::string kFloor = FLEETLOC_SOURCE_DIR "/deploy/demo/floors/moss_2560x1600.jpg";

TEST(CliReloc, FramesOfASimulatedRunAreFoundWithinTwoMillimetresAndTheIndexIsCached) {
  const ScratchDir dir("cli_reloc");
  const std::string mosaic = dir / "floor.db", run = dir / "run";
  ASSERT_EQ(
      RunFleetctl("mosaic import " + Quote(kFloor) + " --resolution 0.0005 --out " + Quote(mosaic))
          .exit_code,
      0);
  ASSERT_EQ(
      RunFleetctl("sim --mosaic " + Quote(mosaic) + " --out " + Quote(run) + " --frames 8 --seed 4")
          .exit_code,
      0);
  for (int frame : {0, 7}) {
    const CommandResult r = RunFleetctl("reloc --mosaic " + Quote(mosaic) + " --run " + Quote(run) +
                                        " --frame " + std::to_string(frame));
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["found"].get<bool>());
    EXPECT_LT(j["error"]["position_m"].get<double>(), 0.002);
    EXPECT_LT(j["error"]["heading_rad"].get<double>(), 0.5 * M_PI / 180);
    EXPECT_EQ(j["index"]["from_cache"].get<bool>(), frame != 0);  // built by the first call
  }
}

TEST(CliReloc, MissingFilesAndFramesAreBadInput) {
  const ScratchDir dir("cli_reloc_bad");
  const CommandResult no_run =
      RunFleetctl("reloc --mosaic " + Quote(dir / "none.db") + " --run " + Quote(dir / "none"));
  EXPECT_EQ(no_run.exit_code, 2);
  EXPECT_NE(no_run.err.find("none"), std::string::npos) << no_run.err;
}

}  // namespace
}  // namespace fleetloc::testing
