// Tests for camera.json: the contract's example, exact round trips, and one error per bad field.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "run_io/run.h"
#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

using testing::HasError;
using testing::TempDir;
using testing::WriteText;

// docs/formats.md, verbatim.
constexpr char kContractExample[] = R"({
  "format": "fleetloc-camera/1",
  "width": 640, "height": 480,
  "resolution": 0.0005,
  "principal_point": [320.0, 240.0],
  "mount": {"x": 0.40, "y": 0.0, "yaw": 0.0},
  "raw": null
})";

class CameraJsonTest : public ::testing::Test {
 protected:
  // The contract example with one member replaced (or, with value "", removed).
  Status ReadWithMember(const std::string& key, const std::string& value) {
    nlohmann::json document = nlohmann::json::parse(kContractExample);
    if (value.empty()) {
      document.erase(key);
    } else {
      document[key] = nlohmann::json::parse(value);
    }
    WriteText(path_, document.dump());
    return ReadCameraJson(path_).status();
  }
  TempDir dir_;
  std::filesystem::path path_ = dir_.path() / "camera.json";
};

TEST_F(CameraJsonTest, ReadsTheContractExample) {
  WriteText(path_, kContractExample);
  Result<CameraFile> camera = ReadCameraJson(path_);
  ASSERT_TRUE(camera.ok()) << camera.status().message();
  EXPECT_EQ(camera->model.width_px, 640);
  EXPECT_EQ(camera->model.height_px, 480);
  EXPECT_EQ(camera->model.resolution_m, 0.0005);
  EXPECT_EQ(camera->model.cx_px, 320.0);
  EXPECT_EQ(camera->model.cy_px, 240.0);
  EXPECT_EQ(camera->model.mount.x, 0.40);
  EXPECT_EQ(camera->model.mount.theta, 0.0);
  EXPECT_FALSE(camera->raw.has_value());
}

TEST_F(CameraJsonTest, RoundTripWithRawBlockIsExact) {
  CameraFile camera;
  camera.model = {1280, 960, 0.00031, 641.25, 479.5, {0.35, -0.02, -2.5}};
  camera.raw = RawCamera{{900.1, 0, 640.3, 0, 899.7, 480.2, 0, 0, 1},
                         {-0.1, 0.01, 1e-4, -2e-4, 0.001},
                         {1e-4, 2e-6, -0.03, -3e-6, 1e-4, 0.02, 1e-7, 2e-7, 1.0}};
  ASSERT_TRUE(WriteCameraJson(path_, camera).ok());
  Result<CameraFile> read = ReadCameraJson(path_);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->model.width_px, 1280);
  EXPECT_EQ(read->model.height_px, 960);
  EXPECT_EQ(read->model.resolution_m, 0.00031);
  EXPECT_EQ(read->model.cx_px, 641.25);
  EXPECT_EQ(read->model.cy_px, 479.5);
  EXPECT_EQ(read->model.mount.x, 0.35);
  EXPECT_EQ(read->model.mount.y, -0.02);
  EXPECT_EQ(read->model.mount.theta, -2.5);
  ASSERT_TRUE(read->raw.has_value());
  EXPECT_EQ(read->raw->K, camera.raw->K);
  EXPECT_EQ(read->raw->dist, camera.raw->dist);
  EXPECT_EQ(read->raw->H_ground, camera.raw->H_ground);
}

TEST_F(CameraJsonTest, UnknownKeysAreRejectedNamingTheKey) {
  // A typo must not silently leave a field at its default (issue 22).
  EXPECT_TRUE(HasError(ReadWithMember("resolutoin", "0.001"), StatusCode::kInvalidInput, path_, 0,
                       "resolutoin"));
  EXPECT_TRUE(HasError(ReadWithMember("mount", R"({"x": 0.4, "y": 0, "yaw": 0, "z": 0.3})"),
                       StatusCode::kInvalidInput, path_, 0, "mount.z"));
  EXPECT_TRUE(HasError(ReadWithMember("raw", R"({"K": [1,0,0, 0,1,0, 0,0,1], "dist": [0,0,0,0],
                                                  "H_ground": [1,0,0, 0,1,0, 0,0,1], "skew": 0})"),
                       StatusCode::kInvalidInput, path_, 0, "raw.skew"));
}

TEST_F(CameraJsonTest, YawIsWrapped) {
  ASSERT_TRUE(ReadWithMember("mount", R"({"x": 0.4, "y": 0, "yaw": 4.0})").ok());
  Result<CameraFile> camera = ReadCameraJson(path_);
  ASSERT_TRUE(camera.ok());
  EXPECT_NEAR(camera->model.mount.theta, 4.0 - 2 * M_PI, 1e-15);
}

TEST_F(CameraJsonTest, MissingFileIsNotFound) {
  EXPECT_TRUE(HasError(ReadCameraJson(path_).status(), StatusCode::kNotFound, path_, 0, ""));
}

TEST_F(CameraJsonTest, SyntaxErrorNamesTheLine) {
  WriteText(path_, "{\n  \"format\": \"fleetloc-camera/1\",\n  \"width\": 640,,\n}\n");
  EXPECT_TRUE(HasError(ReadCameraJson(path_).status(), StatusCode::kInvalidInput, path_, 3, ""));
}

TEST_F(CameraJsonTest, ANumberTooLargeForADoubleIsAnErrorNotAnException) {
  // Found by fuzz_run_files: nlohmann throws out_of_range (not parse_error) for it.
  WriteText(path_, R"({"format": "fleetloc-camera/1", "width": -0.15E8704140835})");
  const Status status = ReadCameraJson(path_).status();
  EXPECT_TRUE(HasError(status, StatusCode::kInvalidInput, path_, 0, "")) << status.message();
  EXPECT_NE(status.message().find("invalid JSON"), std::string::npos) << status.message();
}

TEST_F(CameraJsonTest, TopLevelArrayIsRejected) {
  WriteText(path_, "[1, 2]");
  EXPECT_TRUE(HasError(ReadCameraJson(path_).status(), StatusCode::kInvalidInput, path_, 0, ""));
}

TEST_F(CameraJsonTest, WrongFormatStringNamesFormat) {
  EXPECT_TRUE(HasError(ReadWithMember("format", R"("fleetloc-camera/2")"),
                       StatusCode::kInvalidInput, path_, 0, "format"));
  EXPECT_TRUE(
      HasError(ReadWithMember("format", ""), StatusCode::kInvalidInput, path_, 0, "format"));
}

struct BadMember {
  std::string key;
  std::string value;  // JSON text; "" removes the member
  std::string field;  // the field the message must name
};

class CameraJsonBadMember : public CameraJsonTest,
                            public ::testing::WithParamInterface<BadMember> {};

TEST_P(CameraJsonBadMember, IsInvalidInputNamingFileAndField) {
  const BadMember& bad = GetParam();
  EXPECT_TRUE(
      HasError(ReadWithMember(bad.key, bad.value), StatusCode::kInvalidInput, path_, 0, bad.field));
}

INSTANTIATE_TEST_SUITE_P(
    Types, CameraJsonBadMember,
    ::testing::Values(
        BadMember{"width", R"("640")", "width"}, BadMember{"width", "0", "width"},
        BadMember{"width", "640.5", "width"}, BadMember{"width", "", "width"},
        BadMember{"height", "-480", "height"}, BadMember{"height", "4294967296", "height"},
        BadMember{"resolution", "0", "resolution"}, BadMember{"resolution", "-1e-3", "resolution"},
        BadMember{"resolution", "null", "resolution"},
        BadMember{"resolution", "true", "resolution"},
        BadMember{"principal_point", "[320]", "principal_point"},
        BadMember{"principal_point", R"([320, "240"])", "principal_point[1]"},
        BadMember{"principal_point", R"({"x": 1})", "principal_point"},
        BadMember{"mount", "", "mount"}, BadMember{"mount", "[0, 0, 0]", "mount"},
        BadMember{"mount", R"({"x": 0.4, "y": 0})", "mount.yaw"},
        BadMember{"mount", R"({"x": 0.4, "y": "0", "yaw": 0})", "mount.y"},
        BadMember{"raw", "5", "raw"},
        BadMember{"raw", R"({"dist": [0,0,0,0,0], "H_ground": [1,0,0,0,1,0,0,0,1]})", "raw.K"},
        BadMember{"raw", R"({"K": [1,0,0,0,1,0,0,0], "dist": [0,0,0,0,0],
                             "H_ground": [1,0,0,0,1,0,0,0,1]})",
                  "raw.K"},
        BadMember{"raw", R"({"K": [0,0,0,0,1,0,0,0,1], "dist": [0,0,0,0,0],
                             "H_ground": [1,0,0,0,1,0,0,0,1]})",
                  "raw.K"},
        BadMember{"raw", R"({"K": [1,0,0,0,1,0,0,0,1], "dist": [0,0,0,0,0,0],
                             "H_ground": [1,0,0,0,1,0,0,0,1]})",
                  "raw.dist"},
        BadMember{"raw", R"({"K": [1,0,0,0,1,0,0,0,1], "dist": [0,0,0,0,0],
                             "H_ground": [1,0,0,0,"1",0,0,0,1]})",
                  "raw.H_ground[4]"}));

TEST_F(CameraJsonTest, AcceptsEveryOpenCvDistortionLength) {
  for (int n : {4, 5, 8, 12, 14}) {
    nlohmann::json raw = {{"K", {1, 0, 0, 0, 1, 0, 0, 0, 1}},
                          {"dist", std::vector<double>(n, 0.0)},
                          {"H_ground", {1, 0, 0, 0, 1, 0, 0, 0, 1}}};
    EXPECT_TRUE(ReadWithMember("raw", raw.dump()).ok()) << n;
  }
}

TEST_F(CameraJsonTest, WriterRefusesAnInvalidModel) {
  CameraFile camera;
  camera.model.width_px = 0;
  EXPECT_TRUE(
      HasError(WriteCameraJson(path_, camera), StatusCode::kInvalidInput, path_, 0, "width"));
  camera.model.width_px = 640;
  camera.model.resolution_m = std::nan("");
  EXPECT_TRUE(
      HasError(WriteCameraJson(path_, camera), StatusCode::kInvalidInput, path_, 0, "resolution"));
  EXPECT_FALSE(std::filesystem::exists(path_));
}

}  // namespace
}  // namespace fleetloc::run_io
