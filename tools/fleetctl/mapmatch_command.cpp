// fleetctl mapmatch: the robust SE(2) map fit (docs/cli.md–7, mapmatch/robust_map_fit.h) of
// points.csv against landmarks.csv, searching within --radius of --init; prints the correction as
// JSON on stdout: the contract's keys, then the fit's evidence (support, ambiguity, reason).

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "commands.h"
#include "mapmatch/robust_map_fit.h"
#include "run_io/mapmatch_files.h"
#include "support/parse_numbers.h"

namespace fleetloc::fleetctl {
namespace {

struct MapmatchArgs {
  std::string landmarks;
  std::string points;
  std::string radius;
  std::string final_radius;  // empty: the library's default
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
                      {"covariance", covariance},
                      {"support", fit.support},
                      {"ambiguous", fit.ambiguous},
                      {"runner_up_support", fit.runner_up_support},
                      {"starts", fit.starts},
                      {"final_radius_m", fit.final_radius_m}};
  if (!fit.converged) json["reason"] = fit.reason;
  return json;
}

// One positive number of metres from `text`, or InvalidInput naming `option`.
Result<double> PositiveMetres(const std::string& text, const std::string& option) {
  Result<std::vector<double>> value = ParseNumbers(text, 1, option, "metres");
  if (!value.ok()) return value.status();
  if ((*value)[0] <= 0) return InvalidInput(option + ": must be > 0, got '" + text + "'");
  return (*value)[0];
}

// The fit's options from --radius (the search radius) and --final-radius.
Result<mapmatch::RobustMapFitOptions> FitOptions(const MapmatchArgs& args) {
  mapmatch::RobustMapFitOptions options;
  Result<double> radius = PositiveMetres(args.radius, "--radius");
  if (!radius.ok()) return radius.status();
  options.search_radius_m = *radius;
  if (!args.final_radius.empty()) {
    Result<double> final_radius = PositiveMetres(args.final_radius, "--final-radius");
    if (!final_radius.ok()) return final_radius.status();
    options.final_radius_m = *final_radius;
  }
  return options;
}

// Reads the files, fits around --init and prints the JSON. A fit that cannot be trusted is still
// printed (converged false, the reason, the --init correction) but is "no result": Internal, so
// exit status 1, as `reloc` when it finds nothing (docs/cli.md).
Status RunMapmatch(const MapmatchArgs& args) {
  Result<mapmatch::RobustMapFitOptions> options = FitOptions(args);
  if (!options.ok()) return options.status();
  Result<std::vector<double>> init = ParseNumbers(args.init, 3, "--init", "DX,DY,DTHETA");
  if (!init.ok()) return init.status();
  Result<run_io::LandmarkMap> landmarks = run_io::ReadLandmarksCsv(args.landmarks);
  if (!landmarks.ok()) return landmarks.status();
  Result<std::vector<Eigen::Vector2d>> points = run_io::ReadPointsCsv(args.points);
  if (!points.ok()) return points.status();
  if (landmarks->positions.empty()) return InvalidInput(args.landmarks + ": no landmarks");
  if (points->empty()) return InvalidInput(args.points + ": no points");
  const geometry::Pose2 start{(*init)[0], (*init)[1], (*init)[2]};
  Result<mapmatch::MapFitResult> fit =
      mapmatch::RobustFitMap(landmarks->positions, *points, {}, start, *options);
  if (!fit.ok()) return fit.status();
  std::cout << FitJson(*fit).dump(2) << "\n";
  if (!fit->converged) return Internal("map fit did not converge: " + fit->reason);
  return Status::Ok();
}

}  // namespace

void RegisterMapmatchCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<MapmatchArgs>();
  CLI::App* command =
      app.add_subcommand("mapmatch", "Robust SE(2) fit of measured points to a landmark map");
  command->add_option("--landmarks", args->landmarks, "landmarks.csv (id,x,y)")->required();
  command->add_option("--points", args->points, "points.csv (x,y), in the map frame")->required();
  command
      ->add_option("--radius", args->radius,
                   "Search radius, metres: how far the correction may move a point from where "
                   "--init puts it (also the first kernel radius h)")
      ->required();
  std::ostringstream final_default;
  final_default << mapmatch::RobustMapFitOptions{}.final_radius_m;
  command->add_option("--final-radius", args->final_radius,
                      "Kernel radius h at the end of the fit, metres: about 3x the points' noise "
                      "(default " +
                          final_default.str() + ")");
  command->add_option("--init", args->init, "Initial correction DX,DY,DTHETA (m, m, rad)")
      ->capture_default_str();
  command->callback([args, result] { *result = RunMapmatch(*args); });
}

}  // namespace fleetloc::fleetctl
