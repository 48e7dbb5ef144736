// Tests for forward_camera.json: the documented example, exact round trips, and one error per bad
// field (docs/forward_camera.md).
#include "run_io/forward_camera_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

using testing::HasError;
using testing::TempDir;
using testing::WriteText;

// docs/forward_camera.md's example, verbatim.
constexpr char kDocExample[] = R"({
  "format": "fleetloc-forward-camera/1",
  "width": 640, "height": 480,
  "K": [520.0, 0.0, 320.0, 0.0, 520.0, 240.0, 0.0, 0.0, 1.0],
  "dist": [-0.08, 0.01, 0.0, 0.0, 0.0],
  "mount": {"x": 0.45, "y": 0.0, "yaw": 0.0, "height": 1.0, "pitch": 0.25, "roll": 0.0}
})";

class ForwardCameraJsonTest : public ::testing::Test {
 protected:
  // The example with one member (dotted: "mount.pitch") replaced or, with value "", removed.
  Status ReadWithMember(const std::string& key, const std::string& value) {
    nlohmann::json document = nlohmann::json::parse(kDocExample);
    const std::size_t dot = key.find('.');
    nlohmann::json& parent = dot == std::string::npos ? document : document[key.substr(0, dot)];
    const std::string member = dot == std::string::npos ? key : key.substr(dot + 1);
    if (value.empty()) {
      parent.erase(member);
    } else {
      parent[member] = nlohmann::json::parse(value);
    }
    WriteText(path_, document.dump());
    return ReadForwardCameraJson(path_).status();
  }
  TempDir dir_;
  std::filesystem::path path_ = dir_.path() / "forward_camera.json";
};

TEST_F(ForwardCameraJsonTest, ReadsTheDocumentedExample) {
  WriteText(path_, kDocExample);
  Result<mapmatch::ForwardCameraParams> params = ReadForwardCameraJson(path_);
  ASSERT_TRUE(params.ok()) << params.status().message();
  EXPECT_EQ(params->width_px, 640);
  EXPECT_EQ(params->height_px, 480);
  EXPECT_EQ(params->K[0], 520.0);
  EXPECT_EQ(params->K[5], 240.0);
  EXPECT_EQ(params->dist[0], -0.08);
  EXPECT_EQ(params->mount.x_m, 0.45);
  EXPECT_EQ(params->mount.height_m, 1.0);
  EXPECT_EQ(params->mount.pitch_rad, 0.25);
  EXPECT_TRUE(mapmatch::ForwardCamera::Create(*params).ok());
}

TEST_F(ForwardCameraJsonTest, RoundTripIsExact) {
  mapmatch::ForwardCameraParams params;
  params.width_px = 1280;
  params.height_px = 720;
  params.K = {901.25, 0, 641.5, 0, 899.75, 359.25, 0, 0, 1};
  params.dist = {-0.1, 0.01, 1e-4, -2e-4, 0.001};
  params.mount = {.x_m = 0.52,
                  .y_m = -0.03,
                  .height_m = 1.12,
                  .yaw_rad = -0.1,
                  .pitch_rad = 0.31,
                  .roll_rad = 0.004};
  ASSERT_TRUE(WriteForwardCameraJson(path_, params).ok());
  Result<mapmatch::ForwardCameraParams> read = ReadForwardCameraJson(path_);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->width_px, 1280);
  EXPECT_EQ(read->height_px, 720);
  EXPECT_EQ(read->K, params.K);
  EXPECT_EQ(read->dist, params.dist);
  EXPECT_EQ(read->mount.x_m, 0.52);
  EXPECT_EQ(read->mount.y_m, -0.03);
  EXPECT_EQ(read->mount.yaw_rad, -0.1);
  EXPECT_EQ(read->mount.height_m, 1.12);
  EXPECT_EQ(read->mount.pitch_rad, 0.31);
  EXPECT_EQ(read->mount.roll_rad, 0.004);
}

TEST_F(ForwardCameraJsonTest, RollIsOptional) {
  ASSERT_TRUE(ReadWithMember("mount.roll", "").ok());
  EXPECT_EQ(ReadForwardCameraJson(path_)->mount.roll_rad, 0.0);
}

TEST_F(ForwardCameraJsonTest, MissingFileIsNotFound) {
  EXPECT_TRUE(HasError(ReadForwardCameraJson(path_).status(), StatusCode::kNotFound, path_, 0, ""));
}

TEST_F(ForwardCameraJsonTest, DownwardCameraFileIsRejectedByItsFormat) {
  EXPECT_TRUE(HasError(ReadWithMember("format", R"("fleetloc-camera/1")"),
                       StatusCode::kInvalidInput, path_, 0, "format"));
}

struct BadMember {
  std::string key;    // dotted for mount members
  std::string value;  // JSON text; "" removes the member
  std::string field;  // the field the message must name
};

class ForwardCameraJsonBadMember : public ForwardCameraJsonTest,
                                   public ::testing::WithParamInterface<BadMember> {};

TEST_P(ForwardCameraJsonBadMember, IsInvalidInputNamingFileAndField) {
  const BadMember& bad = GetParam();
  EXPECT_TRUE(
      HasError(ReadWithMember(bad.key, bad.value), StatusCode::kInvalidInput, path_, 0, bad.field));
}

INSTANTIATE_TEST_SUITE_P(
    Fields, ForwardCameraJsonBadMember,
    ::testing::Values(BadMember{"width", "0", "width"}, BadMember{"height", "", "height"},
                      BadMember{"K", "[520, 0, 320, 0, 520, 240, 0, 0]", "K"},
                      BadMember{"K", R"([520, 0, 320, 0, "520", 240, 0, 0, 1])", "K[4]"},
                      BadMember{"K", "[-520, 0, 320, 0, 520, 240, 0, 0, 1]", "K"},
                      BadMember{"K", "[520, 1, 320, 0, 520, 240, 0, 0, 1]", "K"},
                      BadMember{"dist", "[0, 0, 0, 0]", "dist"}, BadMember{"dist", "", "dist"},
                      BadMember{"mount", "", "mount"},
                      BadMember{"mount.height", "", "mount.height"},
                      BadMember{"mount.height", "0", "mount.height"},
                      BadMember{"mount.height", "-1", "mount.height"},
                      BadMember{"mount.pitch", "1.6", "mount.pitch"},
                      BadMember{"mount.pitch", R"("0.2")", "mount.pitch"},
                      BadMember{"mount.x", "null", "mount.x"},
                      BadMember{"mount.roll", "true", "mount.roll"},
                      // Unknown keys, at the top and in the mount (issue 22).
                      BadMember{"fov", "60", "fov"}, BadMember{"mount.z", "0.5", "mount.z"}));

TEST_F(ForwardCameraJsonTest, WriterRefusesNanParameters) {
  mapmatch::ForwardCameraParams params;
  params.mount.height_m = std::nan("");
  EXPECT_TRUE(HasError(WriteForwardCameraJson(path_, params), StatusCode::kInvalidInput, path_, 0,
                       "mount.height"));
  params.mount.height_m = 1.0;
  params.K[2] = std::nan("");
  EXPECT_TRUE(
      HasError(WriteForwardCameraJson(path_, params), StatusCode::kInvalidInput, path_, 0, "K[2]"));
  EXPECT_FALSE(std::filesystem::exists(path_));
}

}  // namespace
}  // namespace fleetloc::run_io
