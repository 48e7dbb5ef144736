// camera.json (docs/formats.md): the rectified camera model, its mount and the optional raw
// block. Unknown keys are rejected, naming the key (issue 22).
#include <algorithm>
#include <initializer_list>
#include <string_view>

#include "geometry/pose2.h"
#include "io/json_fields.h"
#include "run_io/run.h"

namespace fleetloc::run_io {
namespace {

using nlohmann::json;

constexpr char kCameraFormat[] = "fleetloc-camera/1";

Status ReadMount(const io::JsonFields& root, geometry::Pose2* mount) {
  Result<io::JsonFields> fields = root.Object("mount");
  if (!fields.ok()) return fields.status();
  FLEETLOC_RETURN_IF_ERROR(fields->RejectUnknown({"x", "y", "yaw"}));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("x", &mount->x));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("y", &mount->y));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("yaw", &mount->theta));
  mount->theta = geometry::WrapAngle(mount->theta);
  return Status::Ok();
}

// Copies exactly 9 numbers (already size-checked) into a row-major 3×3 array.
std::array<double, 9> ToArray9(const std::vector<double>& values) {
  std::array<double, 9> out{};
  std::copy_n(values.begin(), 9, out.begin());
  return out;
}

Status ReadRaw(const io::JsonFields& root, std::optional<RawCamera>* raw) {
  raw->reset();
  if (!root.Has("raw")) return Status::Ok();
  Result<io::JsonFields> fields = root.Object("raw");
  if (!fields.ok()) return fields.status();
  FLEETLOC_RETURN_IF_ERROR(fields->RejectUnknown({"K", "dist", "H_ground"}));
  RawCamera camera;
  std::vector<double> values;
  FLEETLOC_RETURN_IF_ERROR(fields->Numbers("K", {9}, &values));
  camera.K = ToArray9(values);
  if (camera.K[0] <= 0 || camera.K[4] <= 0) {
    return fields->Error("K", "focal lengths K[0] and K[4] must be positive");
  }
  // The distortion vector lengths cv::undistort accepts.
  FLEETLOC_RETURN_IF_ERROR(fields->Numbers("dist", {4, 5, 8, 12, 14}, &camera.dist));
  FLEETLOC_RETURN_IF_ERROR(fields->Numbers("H_ground", {9}, &values));
  camera.H_ground = ToArray9(values);
  *raw = camera;
  return Status::Ok();
}

Result<CameraFile> ParseCamera(const json& document, const std::filesystem::path& path) {
  const io::JsonFields root(document, path);
  FLEETLOC_RETURN_IF_ERROR(root.CheckFormat(kCameraFormat));
  FLEETLOC_RETURN_IF_ERROR(root.RejectUnknown(
      {"format", "width", "height", "resolution", "principal_point", "mount", "raw"}));
  CameraFile camera;
  geometry::CameraModel& model = camera.model;
  FLEETLOC_RETURN_IF_ERROR(root.PositiveInt("width", &model.width_px));
  FLEETLOC_RETURN_IF_ERROR(root.PositiveInt("height", &model.height_px));
  FLEETLOC_RETURN_IF_ERROR(root.PositiveNumber("resolution", &model.resolution_m));
  std::vector<double> principal_point;
  FLEETLOC_RETURN_IF_ERROR(root.Numbers("principal_point", {2}, &principal_point));
  model.cx_px = principal_point[0];
  model.cy_px = principal_point[1];
  FLEETLOC_RETURN_IF_ERROR(ReadMount(root, &model.mount));
  FLEETLOC_RETURN_IF_ERROR(ReadRaw(root, &camera.raw));
  return camera;
}

json CameraToJson(const CameraFile& camera) {
  const geometry::CameraModel& m = camera.model;
  json document = {
      {"format", kCameraFormat},
      {"width", m.width_px},
      {"height", m.height_px},
      {"resolution", m.resolution_m},
      {"principal_point", {m.cx_px, m.cy_px}},
      {"mount", {{"x", m.mount.x}, {"y", m.mount.y}, {"yaw", geometry::WrapAngle(m.mount.theta)}}},
      {"raw", nullptr},
  };
  if (camera.raw) {
    document["raw"] = {
        {"K", camera.raw->K}, {"dist", camera.raw->dist}, {"H_ground", camera.raw->H_ground}};
  }
  return document;
}

}  // namespace

Result<CameraFile> ReadCameraJson(const std::filesystem::path& path) {
  Result<json> document = io::ReadJsonObjectFile(path);
  if (!document.ok()) return document.status();
  return ParseCamera(*document, path);
}

Status WriteCameraJson(const std::filesystem::path& path, const CameraFile& camera) {
  const json document = CameraToJson(camera);
  // Never write a file that ReadCameraJson would reject (zero width, NaN resolution, ...).
  Result<CameraFile> check = ParseCamera(document, path);
  if (!check.ok()) return check.status();
  return io::WriteJsonFile(path, document);
}

}  // namespace fleetloc::run_io
