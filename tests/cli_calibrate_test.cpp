// fleetctl calibrate on the real chessboard photographs: a camera.json whose raw block the
// readers accept, with a sub-half-pixel reprojection RMS; bad input exits 2 naming the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "run_io/run.h"

namespace fleetloc {
namespace {

std::string Views() {
  std::string list;
  for (int i : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    char name[32];
    std::snprintf(name, sizeof name, "left%02d.jpg", i);
    if (!list.empty()) list += ',';
    list += testing::Quote(FLEETLOC_SOURCE_DIR "/tests/data/calibration/" + std::string(name));
  }
  return list;
}

TEST(CliCalibrate, WritesARawBlockTheReadersAccept) {
  testing::ScratchDir dir("cli_calibrate");
  const std::string out = dir / "camera.json";
  const testing::CommandResult r = testing::RunFleetctl(
      "calibrate --images " + Views() + " --floor-view " +
      testing::Quote(FLEETLOC_SOURCE_DIR "/tests/data/calibration/left01.jpg") + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["views"], 13);
  EXPECT_LT(summary["rms_px"].get<double>(), 0.5);
  auto camera = run_io::ReadCameraJson(out);
  ASSERT_TRUE(camera.ok()) << camera.status().message();
  ASSERT_TRUE(camera->raw.has_value());
  EXPECT_NEAR(camera->raw->K[0], 535.9, 0.02 * 535.9);
  EXPECT_EQ(camera->raw->dist.size(), 5u);
}

TEST(CliCalibrate, BadInputExitsTwoNamingTheProblem) {
  testing::ScratchDir dir("cli_calibrate_bad");
  const std::string floor =
      testing::Quote(FLEETLOC_SOURCE_DIR "/tests/data/calibration/left01.jpg");
  const testing::CommandResult missing = testing::RunFleetctl(
      "calibrate --images /nonexistent/a.jpg --floor-view " + floor + " --out " + (dir / "c.json"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("/nonexistent/a.jpg"), std::string::npos) << missing.err;
  const std::string photos = testing::Quote(FLEETLOC_SOURCE_DIR "/tests/data/brick.png") + "," +
                             testing::Quote(FLEETLOC_SOURCE_DIR "/tests/data/grass.png");
  const testing::CommandResult no_board = testing::RunFleetctl(
      "calibrate --images " + photos + " --floor-view " + floor + " --out " + (dir / "c.json"));
  EXPECT_EQ(no_board.exit_code, 2);
  EXPECT_NE(no_board.err.find("found in 0 images"), std::string::npos) << no_board.err;
  const testing::CommandResult bad_board =
      testing::RunFleetctl("calibrate --images " + Views() + " --board 9by6 --floor-view " + floor +
                           " --out " + (dir / "c.json"));
  EXPECT_EQ(bad_board.exit_code, 2);
  EXPECT_NE(bad_board.err.find("--board"), std::string::npos) << bad_board.err;
}

}  // namespace
}  // namespace fleetloc
