// fleetctl bench mapfit: mean shift vs RANSAC vs ICP on the same map-fit problems (see
// bench_mapfit.h).
#include "bench_mapfit.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <random>
#include <string>
#include <vector>

#include "mapmatch/map_fit.h"
#include "mapmatch/map_fit_problem.h"
#include "peers/map_fit_peers.h"

namespace fleetloc::fleetctl {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct BenchMapFitArgs {
  int trials = 500;  // per outlier level
  unsigned seed = 1;
  std::vector<double> outlier_percents{50, 70, 80, 90};
};

// A 40 m corridor, 2.4 m wide: both ends and a door (two jambs) every ~5 m on each wall.
std::vector<Eigen::Vector2d> CorridorMap(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  std::vector<Eigen::Vector2d> map{{0, -1.2}, {0, 1.2}, {40, -1.2}, {40, 1.2}};
  for (double wall : {-1.2, 1.2}) {
    for (double x = 2.5; x < 38; x += 5.0) {
      const double door = x + jitter(rng);
      map.emplace_back(door, wall);
      map.emplace_back(door + 0.9, wall);
    }
  }
  return map;
}

// One problem: the vehicle somewhere in the corridor sees the landmarks within 4 m.
struct Trial {
  Eigen::Vector2d vehicle;
  mapmatch::MapFitProblem problem;
};

Trial MakeTrial(const std::vector<Eigen::Vector2d>& map, double outlier_fraction,
                std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Trial trial;
  std::vector<int> observed;
  while (observed.size() < 2) {
    trial.vehicle = {2.0 + 36.0 * unit(rng), -0.3 + 0.6 * unit(rng)};
    observed.clear();
    for (std::size_t m = 0; m < map.size(); ++m)
      if ((map[m] - trial.vehicle).norm() < 4.0) observed.push_back(static_cast<int>(m));
  }
  // The pose estimate is 2–5 cm and 1–2° off: a rotation about the vehicle, not the map origin.
  const double heading = 2 * M_PI * unit(rng), shift = 0.02 + 0.03 * unit(rng);
  const double turn = (unit(rng) < 0.5 ? -1 : 1) * (1.0 + unit(rng)) * kDeg;
  const geometry::Pose2 at_vehicle{trial.vehicle.x(), trial.vehicle.y(), 0.0};
  const geometry::Pose2 error{shift * std::cos(heading), shift * std::sin(heading), turn};
  trial.problem = mapmatch::SimulateMapFitProblem(
      map, observed, at_vehicle * error * at_vehicle.Inverse(),
      {.points_per_landmark = 10, .noise_sigma_m = 0.01, .outlier_fraction = outlier_fraction},
      rng);
  return trial;
}

using FitMethod = std::function<mapmatch::MapFitResult(std::span<const Eigen::Vector2d>,
                                                       std::span<const Eigen::Vector2d>)>;
struct Method {
  std::string name;
  FitMethod fit;
};

std::vector<Method> Methods() {
  const mapmatch::MapFitOptions options{.radius_m = 0.3, .final_radius_m = 0.05};
  return {
      {"mean shift",
       [options](auto landmarks, auto points) {
         return mapmatch::FitMap(landmarks, points, {}, {}, options).value();
       }},
      {"RANSAC",
       [](auto landmarks, auto points) { return peers::RansacMapFit(landmarks, points, {}); }},
      {"ICP", [](auto landmarks, auto points) { return peers::IcpMapFit(landmarks, points, {}); }}};
}

struct Score {
  int successes = 0;
  std::vector<double> position_errors_m;
  double seconds = 0.0;
};

// Runs `method` on `trial` and scores it at the vehicle: the correction's error moves the vehicle.
void RunMethod(const Method& method, const std::vector<Eigen::Vector2d>& map, const Trial& trial,
               Score* score) {
  const auto start = std::chrono::steady_clock::now();
  const mapmatch::MapFitResult fit = method.fit(map, trial.problem.points);
  score->seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double position_error =
      (fit.correction * trial.vehicle - trial.problem.truth * trial.vehicle).norm();
  const double rotation_error = mapmatch::ErrorOf(fit.correction, trial.problem.truth).rotation_rad;
  score->position_errors_m.push_back(fit.converged ? position_error : INFINITY);
  if (fit.converged && position_error < 0.01 && rotation_error < 0.5 * kDeg) ++score->successes;
}

double Median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

void PrintHeader(const std::vector<Method>& methods) {
  std::printf("%-9s", "outliers");
  for (const Method& m : methods) std::printf(" | %-30s", m.name.c_str());
  std::printf("\n%-9s", "");
  for (std::size_t k = 0; k < methods.size(); ++k)
    std::printf(" | %8s %11s %9s", "success", "median err", "us/fit");
  std::printf("\n");
}

void PrintRow(double outlier_percent, const std::vector<Score>& scores, int trials) {
  std::printf("%7.0f %%", outlier_percent);
  for (const Score& s : scores) {
    std::printf(" | %7.1f%% %8.1f mm %9.1f", 100.0 * s.successes / trials,
                1e3 * Median(s.position_errors_m), 1e6 * s.seconds / trials);
  }
  std::printf("\n");
  std::fflush(stdout);
}

Status RunBenchMapFit(const BenchMapFitArgs& args) {
  cv::setNumThreads(1);
  std::mt19937 rng(args.seed);
  const std::vector<Eigen::Vector2d> map = CorridorMap(rng);
  const std::vector<Method> methods = Methods();
  std::printf(
      "== map fit: %zu-landmark corridor (40 m x 2.4 m), %d trials per outlier level, seed "
      "%u; 10 points (sigma 1 cm) per landmark within 4 m of the vehicle; start 2-5 cm and "
      "1-2 deg off; success: error at the vehicle < 1 cm and < 0.5 deg\n",
      map.size(), args.trials, args.seed);
  PrintHeader(methods);
  for (const double percent : args.outlier_percents) {
    std::vector<Score> scores(methods.size());
    for (int t = 0; t < args.trials; ++t) {
      const Trial trial = MakeTrial(map, percent / 100.0, rng);
      for (std::size_t k = 0; k < methods.size(); ++k)
        RunMethod(methods[k], map, trial, &scores[k]);
      if ((t + 1) % 100 == 0)
        spdlog::info("{} % outliers: {}/{} trials", percent, t + 1, args.trials);
    }
    PrintRow(percent, scores, args.trials);
  }
  return Status::Ok();
}

}  // namespace

void RegisterBenchMapFit(CLI::App& bench, Status* result) {
  auto args = std::make_shared<BenchMapFitArgs>();
  CLI::App* command =
      bench.add_subcommand("mapfit", "Map fit: mean shift vs RANSAC vs ICP on the same problems");
  command->option_defaults()->always_capture_default();
  command->add_option("--trials", args->trials, "Problems per outlier level")
      ->check(CLI::Range(1, 1000000));
  command->add_option("--seed", args->seed, "Simulation seed");
  command->add_option("--outliers", args->outlier_percents, "Outlier percentages")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 99.0));
  command->callback([args, result] { *result = RunBenchMapFit(*args); });
}

}  // namespace fleetloc::fleetctl
