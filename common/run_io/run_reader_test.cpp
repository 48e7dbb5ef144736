// Tests for ReadRun: a valid run reads back, and every way a run can break the contract is
// reported with the right status code and a message naming the file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "run_io/forward_camera_json.h"
#include "run_io/run.h"
#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;
using testing::HasError;
using testing::TempDir;
using testing::WriteText;

constexpr char kValidRunJson[] = R"({"format": "fleetloc-run/1", "vehicle_id": "agv-7",
  "camera": "camera.json",
  "initial_pose": {"x": 1.0, "y": 2.0, "theta": 0.5, "sigma": [0.01, 0.02, 0.03]}})";

class ReadRunTest : public ::testing::Test {
 protected:
  void SetUp() override { written_ = testing::WriteValidRun(run_dir_); }
  fs::path File(const std::string& name) const { return run_dir_ / name; }
  // Replaces one file of the valid run and reads the run.
  Status ReadWith(const std::string& name, const std::string& text) {
    WriteText(File(name), text);
    return ReadRun(run_dir_).status();
  }
  Status ReadWithRunJson(const std::string& key, const std::string& value) {
    nlohmann::json document = nlohmann::json::parse(kValidRunJson);
    document[key] = nlohmann::json::parse(value);
    return ReadWith("run.json", document.dump());
  }

  TempDir dir_;
  fs::path run_dir_ = dir_.path() / "run";
  run_io::Run written_;
};

TEST_F(ReadRunTest, ReadsAValidRun) {
  Result<run_io::Run> run = ReadRun(run_dir_);
  ASSERT_TRUE(run.ok()) << run.status().message();
  EXPECT_EQ(run->dir, run_dir_);
  EXPECT_EQ(run->vehicle_id, "agv-7");
  EXPECT_EQ(run->camera.model.width_px, 16);
  EXPECT_EQ(run->initial_pose.x, 1.0);
  EXPECT_EQ(run->initial_pose.theta, 0.5);
  EXPECT_EQ(run->initial_sigma, Eigen::Vector3d(0.01, 0.02, 0.03));
  ASSERT_EQ(run->frames.size(), 3u);
  EXPECT_EQ(run->frames[2].t, written_.frames[2].t);
  EXPECT_EQ(run->frames[2].file, run_dir_ / "img" / "f2.png");
  ASSERT_EQ(run->odometry.size(), 5u);
  EXPECT_EQ(run->odometry[4].pose.theta, written_.odometry[4].pose.theta);
  ASSERT_EQ(run->truth.size(), 3u);
  EXPECT_EQ(run->truth[1].pose.x, written_.truth[1].pose.x);
}

TEST_F(ReadRunTest, TruthIsOptional) {
  fs::remove(File("truth.csv"));
  Result<run_io::Run> run = ReadRun(run_dir_);
  ASSERT_TRUE(run.ok()) << run.status().message();
  EXPECT_TRUE(run->truth.empty());
}

TEST_F(ReadRunTest, AnglesAreWrappedAndTrailingEmptyLinesAccepted) {
  ASSERT_TRUE(ReadWith("odometry.csv",
                       "t,x,y,theta\n0,0,0,4.0\n0.1,0,0,-3.5\n0.2,0,0,3.14\n"
                       "0.3,0,0,0\n\n\n")
                  .ok());
  Result<run_io::Run> run = ReadRun(run_dir_);
  ASSERT_TRUE(run.ok());
  EXPECT_NEAR(run->odometry[0].pose.theta, 4.0 - 2 * M_PI, 1e-15);
  EXPECT_NEAR(run->odometry[1].pose.theta, -3.5 + 2 * M_PI, 1e-15);
  EXPECT_EQ(run->odometry[2].pose.theta, 3.14);
}

TEST_F(ReadRunTest, MissingFilesAreNotFound) {
  EXPECT_TRUE(HasError(ReadRun(dir_.path() / "nope").status(), StatusCode::kNotFound,
                       dir_.path() / "nope", 0, ""));
  // Removed in reverse reading order, so each removal is the first error ReadRun meets.
  for (const std::string name : {"odometry.csv", "frames.csv", "camera.json", "run.json"}) {
    fs::remove(File(name));
    EXPECT_TRUE(HasError(ReadRun(run_dir_).status(), StatusCode::kNotFound, File(name), 0, ""))
        << name;
  }
}

TEST_F(ReadRunTest, RunJsonErrorsNameTheField) {
  const StatusCode bad = StatusCode::kInvalidInput;
  EXPECT_TRUE(HasError(ReadWithRunJson("format", R"("fleetloc-run/0")"), bad, File("run.json"), 0,
                       "format"));
  EXPECT_TRUE(
      HasError(ReadWithRunJson("vehicle_id", R"("")"), bad, File("run.json"), 0, "vehicle_id"));
  EXPECT_TRUE(HasError(ReadWithRunJson("vehicle_id", "7"), bad, File("run.json"), 0, "vehicle_id"));
  EXPECT_TRUE(HasError(ReadWithRunJson("initial_pose", R"({"x":1,"y":2,"sigma":[0,0,0]})"), bad,
                       File("run.json"), 0, "initial_pose.theta"));
  EXPECT_TRUE(HasError(ReadWithRunJson("initial_pose", R"({"x":1,"y":2,"theta":0,"sigma":[0,0]})"),
                       bad, File("run.json"), 0, "initial_pose.sigma"));
}

// A mistyped key must not be silently ignored (issue 22).
TEST_F(ReadRunTest, UnknownRunJsonKeysAreRejectedByName) {
  const StatusCode bad = StatusCode::kInvalidInput;
  const Status top = ReadWithRunJson("vehicle", R"("agv-8")");
  EXPECT_TRUE(HasError(top, bad, File("run.json"), 0, "vehicle"));
  EXPECT_NE(top.message().find("unknown key"), std::string::npos) << top.message();
  EXPECT_TRUE(HasError(
      ReadWithRunJson("initial_pose", R"({"x":1,"y":2,"theta":0,"sigma":[0,0,0],"yaw":1})"), bad,
      File("run.json"), 0, "initial_pose.yaw"));
}

TEST_F(ReadRunTest, NegativeSigmaNamesTheElement) {
  EXPECT_TRUE(
      HasError(ReadWithRunJson("initial_pose", R"({"x":1,"y":2,"theta":0,"sigma":[0.1,-0.2,0.1]})"),
               StatusCode::kInvalidInput, File("run.json"), 0, "initial_pose.sigma[1]"));
}

TEST_F(ReadRunTest, CameraErrorsNameTheCameraFile) {
  EXPECT_TRUE(HasError(ReadWith("camera.json", R"({"format": "fleetloc-camera/1", "width": "16"})"),
                       StatusCode::kInvalidInput, File("camera.json"), 0, "width"));
}

TEST_F(ReadRunTest, FramesCsvErrorsNameFileLineAndField) {
  const StatusCode bad = StatusCode::kInvalidInput;
  const fs::path csv = File("frames.csv");
  EXPECT_TRUE(HasError(ReadWith("frames.csv", "time,file\n0,img/f0.png\n"), bad, csv, 1, "t"));
  EXPECT_TRUE(HasError(ReadWith("frames.csv", "t,file\n0,img/f0.png\n0.1\n"), bad, csv, 3, "file"));
  EXPECT_TRUE(
      HasError(ReadWith("frames.csv", "t,file\n0,img/f0.png,x\n"), bad, csv, 2, "(column 3)"));
  EXPECT_TRUE(HasError(ReadWith("frames.csv", "t,file\nzero,img/f0.png\n"), bad, csv, 2, "t"));
  EXPECT_TRUE(
      HasError(ReadWith("frames.csv", "t,file\n0,img/f0.png\nnan,img/f1.png\n"), bad, csv, 3, "t"));
  EXPECT_TRUE(
      HasError(ReadWith("frames.csv", "t,file\n0,img/f0.png\ninf,img/f1.png\n"), bad, csv, 3, "t"));
  EXPECT_TRUE(
      HasError(ReadWith("frames.csv", "t,file\n0,img/f0.png\n0.1,\n"), bad, csv, 3, "file"));
  EXPECT_TRUE(HasError(ReadWith("frames.csv", "t,file\n"), bad, csv, 0, ""));
}

TEST_F(ReadRunTest, NonMonotonicFrameTimesNameTheBreakingLine) {
  const std::string rows = "t,file\n0,img/f0.png\n0.1,img/f1.png\n";
  EXPECT_TRUE(HasError(ReadWith("frames.csv", rows + "0.1,img/f2.png\n"), StatusCode::kInvalidInput,
                       File("frames.csv"), 4, "t"));
  EXPECT_TRUE(HasError(ReadWith("frames.csv", rows + "0.05,img/f2.png\n"),
                       StatusCode::kInvalidInput, File("frames.csv"), 4, "t"));
}

TEST_F(ReadRunTest, MissingFrameImageNamesLineAndFile) {
  const Status status = ReadWith("frames.csv", "t,file\n0,img/f0.png\n0.1,img/missing.png\n");
  EXPECT_TRUE(HasError(status, StatusCode::kNotFound, File("frames.csv"), 3, "file"));
  EXPECT_NE(status.message().find("img/missing.png"), std::string::npos) << status.message();
}

TEST_F(ReadRunTest, OdometryCsvErrorsNameFileLineAndField) {
  const StatusCode bad = StatusCode::kInvalidInput;
  const fs::path csv = File("odometry.csv");
  const std::string header = "t,x,y,theta\n";
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", "t,x,y,yaw\n"), bad, csv, 1, "theta"));
  EXPECT_TRUE(
      HasError(ReadWith("odometry.csv", header + "0,0,0,0\n0.1,0,0\n"), bad, csv, 3, "theta"));
  EXPECT_TRUE(
      HasError(ReadWith("odometry.csv", header + "0,0,0,0,0\n"), bad, csv, 2, "(column 5)"));
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", header + "0,0,zero,0\n"), bad, csv, 2, "y"));
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", header + "0,0,0,NaN\n"), bad, csv, 2, "theta"));
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", header + "0,-inf,0,0\n"), bad, csv, 2, "x"));
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", header + "0,0,0,0\n0.2,0,0,0\n0.1,0,0,0\n"), bad,
                       csv, 4, "t"));
}

TEST_F(ReadRunTest, OdometryMustCoverTheFrames) {
  const StatusCode bad = StatusCode::kInvalidInput;
  const fs::path csv = File("odometry.csv");
  const std::string header = "t,x,y,theta\n";
  // Starts after the first frame (t = 0).
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", header + "0.01,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n"), bad,
                       csv, 2, "t"));
  // Ends before the last frame (t = 0.2).
  EXPECT_TRUE(HasError(ReadWith("odometry.csv", header + "0,0,0,0\n0.1,0,0,0\n0.19,0,0,0\n"), bad,
                       csv, 4, "t"));
  // Fewer samples than frames.
  EXPECT_TRUE(
      HasError(ReadWith("odometry.csv", header + "0,0,0,0\n0.2,0,0,0\n"), bad, csv, 0, "t"));
  EXPECT_TRUE(ReadWith("odometry.csv", header + "-1,0,0,0\n0,0,0,0\n0.2,0,0,0\n").ok());
}

TEST_F(ReadRunTest, TruthMustHaveOneRowPerFrameAtTheSameTime) {
  const StatusCode bad = StatusCode::kInvalidInput;
  const fs::path csv = File("truth.csv");
  const std::string header = "t,x,y,theta\n";
  EXPECT_TRUE(HasError(ReadWith("truth.csv", header + "0,0,0,0\n0.1,0,0,0\n"), bad, csv, 0, "t"));
  EXPECT_TRUE(HasError(ReadWith("truth.csv", header + "0,0,0,0\n0.1,0,0,0\n0.2001,0,0,0\n"), bad,
                       csv, 4, "t"));
  EXPECT_TRUE(HasError(ReadWith("truth.csv", header + "0,0,0,0\n0.1,nan,0,0\n0.2,0,0,0\n"), bad,
                       csv, 3, "x"));
  EXPECT_TRUE(ReadWith("truth.csv", header + "0,0,0,0\n0.1000000005,0,0,0\n0.2,0,0,0\n").ok());
}

// forward/ of the valid run: the default forward camera and two images at t = 0.05 and 0.15.
void WriteForwardDir(const fs::path& run_dir) {
  ASSERT_TRUE(WriteForwardCameraJson(run_dir / "forward" / "forward_camera.json", {}).ok());
  for (int i = 0; i < 2; ++i)
    testing::WriteGrayPng(run_dir / "forward" / "img" / (std::to_string(i) + ".png"), 64, 48);
  WriteText(run_dir / "forward" / "forward.csv", "t,file\n0.05,img/0.png\n0.15,img/1.png\n");
}

TEST_F(ReadRunTest, ReadsTheForwardDirectory) {
  WriteForwardDir(run_dir_);
  WriteText(File("forward/truth.csv"), "t,x,y,theta\n0.05,1,2,0\n0.15,1.1,2,0\n");
  const Result<run_io::Run> run = ReadRun(run_dir_);
  ASSERT_TRUE(run.ok()) << run.status().message();
  ASSERT_TRUE(run->forward.has_value());
  EXPECT_EQ(run->forward->camera.width_px, 640);
  ASSERT_EQ(run->forward->frames.size(), 2u);
  EXPECT_EQ(run->forward->frames[1].t, 0.15);
  EXPECT_EQ(run->forward->frames[1].file, run->dir / "forward" / "img" / "1.png");
  ASSERT_EQ(run->forward->truth.size(), 2u);
  EXPECT_EQ(run->forward->truth[1].pose.x, 1.1);
  EXPECT_FALSE(ReadRun(testing::WriteValidRun(dir_.path() / "plain").dir)->forward.has_value());
}

TEST_F(ReadRunTest, ARunMayHaveForwardFramesOnly) {
  WriteForwardDir(run_dir_);
  WriteText(File("frames.csv"), "t,file\n");
  fs::remove(File("truth.csv"));
  const Result<run_io::Run> run = ReadRun(run_dir_);
  ASSERT_TRUE(run.ok()) << run.status().message();
  EXPECT_TRUE(run->frames.empty());
  EXPECT_EQ(run->forward->frames.size(), 2u);
  WriteText(File("forward/forward.csv"), "t,file\n");
  EXPECT_TRUE(
      HasError(ReadRun(run_dir_).status(), StatusCode::kInvalidInput, File("frames.csv"), 0, ""));
}

TEST_F(ReadRunTest, ForwardDirectoryErrorsNameTheFileAndField) {
  const StatusCode bad = StatusCode::kInvalidInput;
  WriteForwardDir(run_dir_);
  nlohmann::json camera =
      nlohmann::json::parse(testing::ReadText(File("forward/forward_camera.json")));
  camera["mount"]["height"] = -1.0;
  EXPECT_TRUE(HasError(ReadWith("forward/forward_camera.json", camera.dump()), bad,
                       File("forward/forward_camera.json"), 0, "mount.height"));
  ASSERT_TRUE(WriteForwardCameraJson(File("forward/forward_camera.json"), {}).ok());
  // Odometry (t = 0 … 0.2) must cover the forward frames too.
  EXPECT_TRUE(HasError(ReadWith("forward/forward.csv", "t,file\n0.05,img/0.png\n0.25,img/1.png\n"),
                       bad, File("odometry.csv"), 6, "t"));
  EXPECT_TRUE(HasError(ReadWith("forward/truth.csv", "t,x,y,theta\n0.05,1,2,0\n"), bad,
                       File("forward/truth.csv"), 0, "t"));
}

}  // namespace
}  // namespace fleetloc::run_io
