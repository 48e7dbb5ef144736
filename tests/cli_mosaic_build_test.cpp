// End to end through the fleetctl command line (docs/cli.md, issue 3): a slow mapping run
// simulated over a real floor photo is built into a mosaic with `fleetctl mosaic build`; the
// mosaic's distortion against the true photo is measured, and a second, fast run with another
// seed is tracked against the built mosaic and scored against its truth.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace fleetloc::testing {
namespace {

const std::string kFloor = FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png";

nlohmann::json RunJson(const std::string& args) {
  const CommandResult r = RunFleetctl(args);
  EXPECT_EQ(r.exit_code, 0) << "fleetctl " << args << "\n" << r.err;
  return nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
}

TEST(CliMosaicBuild, FastRunTracksOnAMosaicBuiltFromASlowMappingRun) {
  const ScratchDir dir("cli_mosaic_build");
  const std::string mapping = dir / "mapping", fast = dir / "fast", built = dir / "built.db";
  // 160 frames of 640×480 at 300 px/s and 5 Hz: 60 px between frames (87 % overlap), a little more
  // than one lap of the figure eight, so the route crosses itself and closes. The mapping run's
  // initial pose is exact: it defines where the map frame lies.
  const nlohmann::json mapping_sim =
      RunJson("sim --image " + Quote(kFloor) + " --resolution 0.0005 --speed-px-s 300 " +
              "--rate-hz 5 --frames 160 --route figure8 --seed 11 --no-initial-perturb --out " +
              Quote(mapping));
  ASSERT_FALSE(mapping_sim.is_discarded());
  ASSERT_GT(mapping_sim["laps"].get<double>(), 1.0);

  const nlohmann::json build =
      RunJson("mosaic build --run " + Quote(mapping) + " --out " + Quote(built));
  ASSERT_FALSE(build.is_discarded());
  EXPECT_EQ(build["successive_registered"], 159);
  EXPECT_GE(build["loop_closures"].get<int>(), 10);  // the crossing and the lap's end
  // Measured: camera positions of the mapped frames 0.044 px RMS, 0.09 px max from truth.
  EXPECT_LT(build["truth"]["camera_position_rms_px"].get<double>(), 0.1);
  EXPECT_LT(build["truth"]["camera_position_max_px"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(build["resolution"].get<double>(), 0.0005);

  // Measured: 0.04 px RMS, 0.11 px max; scale error below 1 ppm.
  const nlohmann::json distortion = RunJson("bench mosaic-distortion --mosaic " + Quote(built) +
                                            " --truth " + Quote(kFloor) + " --resolution 0.0005");
  ASSERT_FALSE(distortion.is_discarded());
  EXPECT_GT(distortion["patches"].get<int>(), 200);
  EXPECT_LT(distortion["rms_px"].get<double>(), 0.1);
  EXPECT_LT(distortion["max_px"].get<double>(), 0.3);
  EXPECT_LT(std::abs(distortion["scale_error_ppm"].get<double>()), 100.0);

  // The fast run: default 3000 px/s (600 px between frames: no overlap), another seed.
  ASSERT_FALSE(RunJson("sim --image " + Quote(kFloor) + " --resolution 0.0005 --frames 60 " +
                       "--seed 12 --out " + Quote(fast))
                   .is_discarded());
  const nlohmann::json tracked = RunJson("track --mosaic " + Quote(built) + " --run " +
                                         Quote(fast) + " --out " + Quote(dir / "poses.csv"));
  ASSERT_FALSE(tracked.is_discarded());
  EXPECT_EQ(tracked["frames"], 60);
  EXPECT_GE(tracked["lock_rate"].get<double>(), 0.99);
  // Measured: 0.046 px RMS (0.014 px on the photo imported directly).
  EXPECT_LT(tracked["error"]["camera_position_rms_px"].get<double>(), 0.15);
}

}  // namespace
}  // namespace fleetloc::testing
