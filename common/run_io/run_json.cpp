// run.json reading and writing. Unknown keys are rejected, naming the key (issue 22).
#include "run_io/run_json.h"

#include "io/json_fields.h"
#include "io/messages.h"

namespace fleetloc::run_io {
namespace {

using nlohmann::json;

constexpr char kRunFormat[] = "fleetloc-run/1";

Status ReadInitialPose(const io::JsonFields& root, RunJson* run) {
  Result<io::JsonFields> pose = root.Object("initial_pose");
  if (!pose.ok()) return pose.status();
  FLEETLOC_RETURN_IF_ERROR(pose->RejectUnknown({"x", "y", "theta", "sigma"}));
  FLEETLOC_RETURN_IF_ERROR(pose->Number("x", &run->initial_pose.x));
  FLEETLOC_RETURN_IF_ERROR(pose->Number("y", &run->initial_pose.y));
  FLEETLOC_RETURN_IF_ERROR(pose->Number("theta", &run->initial_pose.theta));
  run->initial_pose.theta = geometry::WrapAngle(run->initial_pose.theta);
  std::vector<double> sigma;
  FLEETLOC_RETURN_IF_ERROR(pose->Numbers("sigma", {3}, &sigma));
  for (int i = 0; i < 3; ++i) {
    if (sigma[i] < 0) {
      return pose->Error("sigma[" + std::to_string(i) + "]",
                         "must not be negative, got " + io::FormatDouble(sigma[i]));
    }
    run->initial_sigma[i] = sigma[i];
  }
  return Status::Ok();
}

Result<RunJson> ParseRun(const json& document, const std::filesystem::path& path) {
  const io::JsonFields root(document, path);
  FLEETLOC_RETURN_IF_ERROR(root.CheckFormat(kRunFormat));
  FLEETLOC_RETURN_IF_ERROR(root.RejectUnknown({"format", "vehicle_id", "camera", "initial_pose"}));
  RunJson run;
  FLEETLOC_RETURN_IF_ERROR(root.NonEmptyString("vehicle_id", &run.vehicle_id));
  std::string camera;
  FLEETLOC_RETURN_IF_ERROR(root.NonEmptyString("camera", &camera));
  run.camera = camera;
  FLEETLOC_RETURN_IF_ERROR(ReadInitialPose(root, &run));
  return run;
}

json RunToJson(const RunJson& run) {
  const geometry::Pose2& p = run.initial_pose;
  return {{"format", kRunFormat},
          {"vehicle_id", run.vehicle_id},
          {"camera", run.camera.generic_string()},
          {"initial_pose",
           {{"x", p.x},
            {"y", p.y},
            {"theta", geometry::WrapAngle(p.theta)},
            {"sigma", {run.initial_sigma.x(), run.initial_sigma.y(), run.initial_sigma.z()}}}}};
}

}  // namespace

Result<RunJson> ReadRunJson(const std::filesystem::path& path) {
  Result<json> document = io::ReadJsonObjectFile(path);
  if (!document.ok()) return document.status();
  return ParseRun(*document, path);
}

Status WriteRunJson(const std::filesystem::path& path, const RunJson& run) {
  const json document = RunToJson(run);
  Result<RunJson> check = ParseRun(document, path);
  if (!check.ok()) return check.status();
  return io::WriteJsonFile(path, document);
}

}  // namespace fleetloc::run_io
