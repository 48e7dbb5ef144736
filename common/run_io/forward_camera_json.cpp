// forward_camera.json reader and writer (see forward_camera_json.h). Unknown keys are rejected,
// naming the key (issue 22).
#include "run_io/forward_camera_json.h"

#include <algorithm>

#include "geometry/pose2.h"
#include "io/json_fields.h"

namespace fleetloc::run_io {
namespace {

using mapmatch::ForwardCameraParams;
using nlohmann::json;

constexpr char kForwardCameraFormat[] = "fleetloc-forward-camera/1";

// Reads `key` as exactly N numbers into `out`.
template <std::size_t N>
Status ReadArray(const io::JsonFields& fields, std::string_view key, std::array<double, N>* out) {
  std::vector<double> values;
  FLEETLOC_RETURN_IF_ERROR(fields.Numbers(key, {N}, &values));
  std::copy_n(values.begin(), N, out->begin());
  return Status::Ok();
}

Status ReadMount(const io::JsonFields& root, mapmatch::ForwardMount* mount) {
  Result<io::JsonFields> fields = root.Object("mount");
  if (!fields.ok()) return fields.status();
  FLEETLOC_RETURN_IF_ERROR(fields->RejectUnknown({"x", "y", "yaw", "height", "pitch", "roll"}));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("x", &mount->x_m));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("y", &mount->y_m));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("yaw", &mount->yaw_rad));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("height", &mount->height_m));
  FLEETLOC_RETURN_IF_ERROR(fields->Number("pitch", &mount->pitch_rad));
  mount->roll_rad = 0.0;
  if (fields->Has("roll")) FLEETLOC_RETURN_IF_ERROR(fields->Number("roll", &mount->roll_rad));
  mount->yaw_rad = geometry::WrapAngle(mount->yaw_rad);
  return Status::Ok();
}

Result<ForwardCameraParams> Parse(const json& document, const std::filesystem::path& path) {
  const io::JsonFields root(document, path);
  FLEETLOC_RETURN_IF_ERROR(root.CheckFormat(kForwardCameraFormat));
  FLEETLOC_RETURN_IF_ERROR(root.RejectUnknown({"format", "width", "height", "K", "dist", "mount"}));
  ForwardCameraParams params;
  FLEETLOC_RETURN_IF_ERROR(root.PositiveInt("width", &params.width_px));
  FLEETLOC_RETURN_IF_ERROR(root.PositiveInt("height", &params.height_px));
  FLEETLOC_RETURN_IF_ERROR(ReadArray(root, "K", &params.K));
  FLEETLOC_RETURN_IF_ERROR(ReadArray(root, "dist", &params.dist));
  FLEETLOC_RETURN_IF_ERROR(ReadMount(root, &params.mount));
  // Range checks shared with the model; their field names are this file's dotted names.
  if (auto problem = mapmatch::FindProblem(params))
    return root.Error(problem->field, problem->what);
  return params;
}

json ToJson(const ForwardCameraParams& p) {
  const mapmatch::ForwardMount& m = p.mount;
  return {{"format", kForwardCameraFormat},
          {"width", p.width_px},
          {"height", p.height_px},
          {"K", p.K},
          {"dist", p.dist},
          {"mount",
           {{"x", m.x_m},
            {"y", m.y_m},
            {"yaw", geometry::WrapAngle(m.yaw_rad)},
            {"height", m.height_m},
            {"pitch", m.pitch_rad},
            {"roll", m.roll_rad}}}};
}

}  // namespace

Result<ForwardCameraParams> ReadForwardCameraJson(const std::filesystem::path& path) {
  Result<json> document = io::ReadJsonObjectFile(path);
  if (!document.ok()) return document.status();
  return Parse(*document, path);
}

Status WriteForwardCameraJson(const std::filesystem::path& path,
                              const ForwardCameraParams& params) {
  const json document = ToJson(params);
  Result<ForwardCameraParams> check = Parse(document, path);
  if (!check.ok()) return check.status();
  return io::WriteJsonFile(path, document);
}

}  // namespace fleetloc::run_io
