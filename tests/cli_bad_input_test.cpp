// Bad input through the fleetctl command line (docs/cli.md): every broken file must end the
// command with exit status 2 and one line on stderr naming the file (and line and field where
// there are such) — never a crash, a hang or a silently wrong result. Each test breaks one thing
// in a fresh copy of a valid run over a valid mosaic, built once per test suite.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace fleetloc::testing {
namespace {

namespace fs = std::filesystem;

const std::string kFloor = FLEETLOC_SOURCE_DIR "/deploy/demo/floors/gravel_1024.png";
const std::string kOtherSizeImage = FLEETLOC_SOURCE_DIR "/tests/data/gravel.png";  // 512 x 512

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

void WriteRandomBytes(const fs::path& path, std::size_t count) {
  std::mt19937 random(7);
  std::string bytes(count, '\0');
  for (char& b : bytes) b = static_cast<char>(random() & 0xff);
  WriteText(path, bytes);
}

// Sets field `column` of line `line_number` (1-based, the header is line 1) of a CSV file.
void SetCsvField(const fs::path& path, int line_number, int column, const std::string& value) {
  std::istringstream in(ReadWhole(path));
  std::string out;
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    if (++number == line_number) {
      std::vector<std::string> fields;
      std::istringstream cells(line);
      for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
      fields.at(column) = value;
      line.clear();
      for (std::size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + fields[i];
    }
    out += line + "\n";
  }
  WriteText(path, out);
}

// Field `column` of line `line_number` of a CSV file.
std::string CsvField(const fs::path& path, int line_number, int column) {
  std::istringstream in(ReadWhole(path));
  std::string line;
  for (int i = 0; i < line_number; ++i) std::getline(in, line);
  std::istringstream cells(line);
  std::string cell;
  for (int i = 0; i <= column; ++i) std::getline(cells, cell, ',');
  return cell;
}

class CliBadInput : public ::testing::Test {
 protected:
  // The valid mosaic and run (6 frames of 320 x 240 over a real gravel photo) every test starts
  // from; a failure here fails every test with the command's error.
  static void SetUpTestSuite() {
    base_ = new ScratchDir("cli_bad_input_base");
    mosaic_ = *base_ / "floor.db";
    base_run_ = *base_ / "run";
    for (const std::string& command :
         {"mosaic import " + Quote(kFloor) + " --resolution 0.0005 --out " + Quote(mosaic_),
          "sim --mosaic " + Quote(mosaic_) + " --out " + Quote(base_run_) +
              " --frames 6 --width 320 --height 240 --seed 3"}) {
      const CommandResult r = RunFleetctl(command);
      if (r.exit_code != 0) {
        setup_error_ = "fleetctl " + command + ": " + r.err;
        return;
      }
    }
  }
  static void TearDownTestSuite() {
    delete base_;
    base_ = nullptr;
  }

  void SetUp() override {
    ASSERT_TRUE(setup_error_.empty()) << setup_error_;
    fs::copy(base_run_, run_, fs::copy_options::recursive);
  }

  // `fleetctl track` of `run` over `mosaic` into this test's scratch directory.
  CommandResult Track(const std::string& run, const std::string& mosaic,
                      const std::string& more = "") const {
    return RunFleetctl("track --mosaic " + Quote(mosaic) + " --run " + Quote(run) + " --out " +
                       Quote(poses_) + more);
  }
  CommandResult TrackCopy() const { return Track(run_, mosaic_); }

  static inline ScratchDir* base_ = nullptr;
  static inline std::string mosaic_, base_run_, setup_error_;
  const ScratchDir dir_{"cli_bad_input"};
  const std::string run_ = dir_ / "run";
  const std::string poses_ = dir_ / "poses.csv";
};

TEST_F(CliBadInput, UntouchedCopyOfTheBaseRunTracks) {
  const CommandResult r = TrackCopy();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(poses_));
}

TEST_F(CliBadInput, TrackMissingRunDirectory) {
  EXPECT_TRUE(IsBadInput(Track(dir_ / "no_such_run", mosaic_), {"no_such_run"}));
}

TEST_F(CliBadInput, OdometryNanOnLineFiveNamesLineAndField) {
  SetCsvField(fs::path(run_) / "odometry.csv", 5, 1, "nan");
  const CommandResult r = TrackCopy();
  EXPECT_TRUE(IsBadInput(r, {"odometry.csv:5", "field 'x'"}));
  EXPECT_FALSE(fs::exists(poses_));
}

TEST_F(CliBadInput, OdometryTimeGoingBackwardsNamesLineAndField) {
  const fs::path odometry = fs::path(run_) / "odometry.csv";
  SetCsvField(odometry, 5, 0, CsvField(odometry, 3, 0));
  EXPECT_TRUE(IsBadInput(TrackCopy(), {"odometry.csv:5", "field 't'"}));
}

TEST_F(CliBadInput, FramesCsvNamingAMissingPng) {
  SetCsvField(fs::path(run_) / "frames.csv", 3, 1, "frames/missing.png");
  const CommandResult r = TrackCopy();
  EXPECT_TRUE(IsBadInput(r, {"missing.png"}));
  EXPECT_FALSE(fs::exists(poses_));
}

TEST_F(CliBadInput, CorruptPngFrame) {
  WriteRandomBytes(fs::path(run_) / "frames/000002.png", 4096);
  const CommandResult r = TrackCopy();
  EXPECT_TRUE(IsBadInput(r, {"000002.png"}));
  EXPECT_FALSE(fs::exists(poses_));
}

TEST_F(CliBadInput, FrameOfTheWrongSize) {
  fs::copy_file(kOtherSizeImage, fs::path(run_) / "frames/000001.png",
                fs::copy_options::overwrite_existing);
  EXPECT_TRUE(IsBadInput(TrackCopy(), {"000001.png"}));
}

TEST_F(CliBadInput, MalformedRunJson) {
  WriteText(fs::path(run_) / "run.json", "{\"format\": \"fleetloc-run/1\", \"vehicle_id\": ");
  EXPECT_TRUE(IsBadInput(TrackCopy(), {"run.json"}));
}

TEST_F(CliBadInput, MosaicThatIsATextFile) {
  const std::string text = dir_ / "notes.db";
  WriteText(text, "this is not a mosaic\n");
  EXPECT_TRUE(IsBadInput(Track(run_, text), {"notes.db"}));
}

TEST_F(CliBadInput, MosaicTruncatedToHalf) {
  const fs::path truncated = dir_ / "truncated.db";
  fs::copy_file(mosaic_, truncated);
  fs::resize_file(truncated, fs::file_size(truncated) / 2);
  const CommandResult r = Track(run_, truncated.string());
  EXPECT_TRUE(IsBadInput(r, {"truncated.db"}));
  EXPECT_FALSE(fs::exists(poses_));
}

TEST_F(CliBadInput, TrackConfigWithAnUnknownOption) {
  const std::string config = dir_ / "tracker.json";
  WriteText(config, "{\"template_size_px\": 48, \"no_such_option\": 1}\n");
  EXPECT_TRUE(IsBadInput(Track(run_, mosaic_, " --config " + Quote(config)),
                         {"tracker.json", "no_such_option"}));
}

// The base run's camera.json with `pattern` replaced by `replacement` (regex); the text replaced.
std::string EditCameraJson(const fs::path& run, const std::string& pattern,
                           const std::string& replacement) {
  const fs::path camera = run / "camera.json";
  const std::string text = testing::ReadWhole(camera);
  std::smatch found;
  EXPECT_TRUE(std::regex_search(text, found, std::regex(pattern))) << text;
  WriteText(camera, std::regex_replace(text, std::regex(pattern), replacement));
  return found.str(1);
}

TEST_F(CliBadInput, CameraJsonWithAnUnknownKeyNamesIt) {
  EditCameraJson(run_, R"re(("width"))re", R"re("resolutoin": 0.001, $1)re");
  EXPECT_TRUE(IsBadInput(TrackCopy(), {"camera.json", "resolutoin", "unknown key"}));
}

TEST_F(CliBadInput, RunJsonWithAnUnknownKeyNamesIt) {
  // Before issue 22 a mistyped key in run.json was ignored.
  const fs::path run_json = fs::path(run_) / "run.json";
  const std::string text = testing::ReadWhole(run_json);
  WriteText(run_json, std::regex_replace(text, std::regex(R"re("vehicle_id")re"),
                                         R"re("vehicle_name": "agv-x", "vehicle_id")re"));
  EXPECT_TRUE(IsBadInput(TrackCopy(), {"run.json", "vehicle_name", "unknown key"}));
}

TEST_F(CliBadInput, CameraAtTwiceTheMosaicsResolutionIsRefusedWithBothValues) {
  // Before issue 22 this lost almost every frame and exited 0.
  const std::string mosaic_resolution =
      EditCameraJson(run_, R"re("resolution": ([0-9.e-]+))re", R"re("resolution": 0.001)re");
  ASSERT_EQ(mosaic_resolution, "0.0005") << "the base run is at the mosaic's resolution";
  const CommandResult r = TrackCopy();
  EXPECT_TRUE(IsBadInput(r, {"camera resolution 0.001 m/px", "the mosaic's 0.0005 m/px", "5 %"}));
  EXPECT_FALSE(fs::exists(poses_));
}

TEST_F(CliBadInput, TrackFramesOutOntoADirectoryIsAnErrorNamingIt) {
  const std::string target = dir_ / "frames_dir";
  fs::create_directories(target);
  const CommandResult r = Track(run_, mosaic_, " --frames-out " + Quote(target));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("frames_dir"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_directory(target));  // left as it was
}

TEST_F(CliBadInput, MosaicImportOfACorruptImage) {
  const std::string image = dir_ / "corrupt.png";
  WriteRandomBytes(image, 8192);
  const CommandResult r = RunFleetctl("mosaic import " + Quote(image) +
                                      " --resolution 0.001 --out " + Quote(dir_ / "corrupt.db"));
  EXPECT_TRUE(IsBadInput(r, {"corrupt.png"}));
  EXPECT_FALSE(fs::exists(dir_ / "corrupt.db"));
}

TEST_F(CliBadInput, MosaicImportOfAMissingFile) {
  const CommandResult r = RunFleetctl("mosaic import " + Quote(dir_ / "absent.png") +
                                      " --resolution 0.001 --out " + Quote(dir_ / "absent.db"));
  EXPECT_TRUE(IsBadInput(r, {"absent.png"}));
}

TEST_F(CliBadInput, MosaicInfoOfATextFile) {
  const std::string text = dir_ / "readme.txt";
  WriteText(text, "hello\n");
  EXPECT_TRUE(IsBadInput(RunFleetctl("mosaic info " + Quote(text)), {"readme.txt"}));
}

TEST_F(CliBadInput, SimWithAMissingImage) {
  const CommandResult r = RunFleetctl("sim --image " + Quote(dir_ / "absent.png") +
                                      " --resolution 0.0005 --out " + Quote(dir_ / "sim"));
  EXPECT_TRUE(IsBadInput(r, {"absent.png"}));
}

TEST_F(CliBadInput, BenchMosaicWithAMalformedSize) {
  const CommandResult r = RunFleetctl("bench mosaic --sizes 600x400,800by600 --work-dir " +
                                      Quote(dir_ / "bench_mosaic"));
  EXPECT_TRUE(IsBadInput(r, {"--sizes", "800by600"}));
}

TEST_F(CliBadInput, ComposeFloorOfASizeToAPngOrFromAMissingPhoto) {
  const CommandResult png = RunFleetctl("compose-floor " + Quote(kFloor) +
                                        " --size 600x400 --out " + Quote(dir_ / "floor.png"));
  EXPECT_TRUE(IsBadInput(png, {"floor.png", "PGM"}));
  const CommandResult missing = RunFleetctl("compose-floor " + Quote(dir_ / "absent.jpg") +
                                            " --size 600x400 --out " + Quote(dir_ / "floor.pgm"));
  EXPECT_TRUE(IsBadInput(missing, {"absent.jpg"}));
  EXPECT_FALSE(fs::exists(dir_ / "floor.pgm"));
}

// `fleetctl mosaic build` of `run`. Its progress lines (stderr) may precede an error found after
// registering: only the last stderr line is kept, so IsBadInput checks the error line itself.
CommandResult BuildMosaic(const std::string& run, const std::string& out) {
  CommandResult r = RunFleetctl("mosaic build --run " + Quote(run) + " --out " + Quote(out));
  const std::size_t end = r.err.find_last_not_of('\n');
  const std::size_t start = end == std::string::npos ? 0 : r.err.rfind('\n', end);
  if (start != std::string::npos && end != std::string::npos) r.err.erase(0, start + 1);
  return r;
}

TEST_F(CliBadInput, MosaicBuildOfARunWhoseFramesDoNotOverlap) {
  // The base run drives 3000 px/s at 5 Hz: 600 px between 320 px frames, nothing to register.
  const std::string out = dir_ / "built.db";
  EXPECT_TRUE(
      IsBadInput(BuildMosaic(run_, out), {"fleetctl: ",
                                          "run: only 0 of 5 successive frame pairs registered (0 "
                                          "overlap by the odometry)"}));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
}

TEST_F(CliBadInput, MosaicBuildOdometryNanNamesLineAndField) {
  SetCsvField(fs::path(run_) / "odometry.csv", 5, 2, "nan");
  EXPECT_TRUE(IsBadInput(BuildMosaic(run_, dir_ / "built.db"), {"odometry.csv:5", "field 'y'"}));
}

TEST_F(CliBadInput, MosaicBuildMissingRunDirectory) {
  EXPECT_TRUE(IsBadInput(BuildMosaic(dir_ / "no_such_run", dir_ / "built.db"), {"no_such_run"}));
}

TEST_F(CliBadInput, MosaicBuildMissingFramesCsv) {
  fs::remove(fs::path(run_) / "frames.csv");
  EXPECT_TRUE(IsBadInput(BuildMosaic(run_, dir_ / "built.db"), {"frames.csv"}));
}

TEST_F(CliBadInput, MosaicBuildNeverOverwritesAMosaic) {
  EXPECT_TRUE(IsBadInput(BuildMosaic(run_, mosaic_), {"floor.db", "already exists"}));
}

}  // namespace
}  // namespace fleetloc::testing
