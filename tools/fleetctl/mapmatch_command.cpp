// fleetctl mapmatch: the robust SE(2) map fit (CONTRACT §6–7) of points.csv against landmarks.csv;
// prints the correction as JSON on stdout.
#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "io/mapmatch_files.h"
#include "mapmatch/map_fit.h"
#include "parse_numbers.h"

namespace fleetloc::fleetctl {
namespace {

struct MapmatchArgs {
  std::string landmarks;
  std::string points;
  std::string radius;
  std::string init = "0,0,0";
};

nlohmann::json FitJson(const mapmatch::MapFitResult& fit) {
  nlohmann::json covariance = nlohmann::json::array();
  for (int r = 0; r < 3; ++r)
    covariance.push_back({fit.covariance(r, 0), fit.covariance(r, 1), fit.covariance(r, 2)});
  nlohmann::json json{{"dx", fit.correction.x},
                      {"dy", fit.correction.y},
                      {"dtheta", fit.correction.theta},
                      {"iterations", fit.iterations},
                      {"inliers", fit.inliers},
                      {"converged", fit.converged},
                      {"landmarks_matched", fit.landmarks_matched},
                      {"rms_residual_m", fit.rms_residual_m},
                      {"covariance", covariance}};
  if (!fit.converged) json["reason"] = fit.reason;
  return json;
}

// Reads the files, fits from --init and prints the JSON. A fit that cannot determine the
// correction is a result (converged false, with the reason), not an error.
Status RunMapmatch(const MapmatchArgs& args) {
  Result<std::vector<double>> radius = ParseNumbers(args.radius, 1, "--radius", "H (metres)");
  if (!radius.ok()) return radius.status();
  if ((*radius)[0] <= 0) return InvalidInput("--radius: must be > 0, got '" + args.radius + "'");
  Result<std::vector<double>> init = ParseNumbers(args.init, 3, "--init", "DX,DY,DTHETA");
  if (!init.ok()) return init.status();
  Result<io::LandmarkMap> landmarks = io::ReadLandmarksCsv(args.landmarks);
  if (!landmarks.ok()) return landmarks.status();
  Result<std::vector<Eigen::Vector2d>> points = io::ReadPointsCsv(args.points);
  if (!points.ok()) return points.status();
  if (landmarks->positions.empty()) return InvalidInput(args.landmarks + ": no landmarks");
  if (points->empty()) return InvalidInput(args.points + ": no points");
  const geometry::Pose2 start{(*init)[0], (*init)[1], (*init)[2]};
  Result<mapmatch::MapFitResult> fit =
      mapmatch::FitMap(landmarks->positions, *points, {}, start, {.radius_m = (*radius)[0]});
  if (!fit.ok()) return fit.status();
  if (!fit->converged) spdlog::warn("map fit did not converge: {}", fit->reason);
  std::cout << FitJson(*fit).dump(2) << "\n";
  return Status::Ok();
}

}  // namespace

void RegisterMapmatchCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<MapmatchArgs>();
  CLI::App* command =
      app.add_subcommand("mapmatch", "Robust SE(2) fit of measured points to a landmark map");
  command->add_option("--landmarks", args->landmarks, "landmarks.csv (id,x,y)")->required();
  command->add_option("--points", args->points, "points.csv (x,y), in the map frame")->required();
  command->add_option("--radius", args->radius, "Kernel radius h, metres")->required();
  command->add_option("--init", args->init, "Initial correction DX,DY,DTHETA (m, m, rad)")
      ->capture_default_str();
  command->callback([args, result] { *result = RunMapmatch(*args); });
}

}  // namespace fleetloc::fleetctl
