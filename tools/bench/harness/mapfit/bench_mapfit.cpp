// fleetctl bench mapfit: mean shift vs RANSAC (two kinds) vs ICP on the same map-fit problems
// (see bench_mapfit.h).
#include "harness/mapfit/bench_mapfit.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "harness/mapfit/bench_mapfit_problems.h"
#include "mapmatch/map_fit.h"
#include "mapmatch/robust_map_fit.h"
#include "peers/map_fit_peers.h"
#include "peers/pair_ransac_map_fit.h"

namespace fleetloc::bench {
namespace {

constexpr double kDeg = M_PI / 180.0;

using FitMethod = std::function<mapmatch::MapFitResult(const MapFitTrial&)>;
struct Method {
  std::string name;
  FitMethod fit;
};

// The local mean shift from the start (FitMap), h starting at the radius hint: shrinking to the
// robust fit's final h, or staying at the hint as `fleetctl mapmatch --radius H` ran before
// issue 16.
mapmatch::MapFitResult LocalFit(const MapFitTrial& t, bool shrink) {
  const double final_radius = mapmatch::RobustMapFitOptions{}.final_radius_m;
  const mapmatch::MapFitOptions options{
      .radius_m = t.radius_hint_m,
      .final_radius_m = shrink ? std::min(final_radius, t.radius_hint_m) : 0.0};
  return mapmatch::FitMap(t.map, t.problem.points, {}, {}, options).value();
}

// The robust fit and the correspondence-free RANSAC search within the problem's radius hint with
// their default options; RANSAC-NN (nearest-landmark pairs under the start) and ICP do not use it.
std::vector<Method> Methods() {
  return {
      {"mean shift (robust)",
       [](const MapFitTrial& t) {
         const mapmatch::RobustMapFitOptions options{.search_radius_m = t.radius_hint_m};
         return mapmatch::RobustFitMap(t.map, t.problem.points, {}, {}, options).value();
       }},
      {"local, h shrinks", [](const MapFitTrial& t) { return LocalFit(t, true); }},
      {"local, h = radius", [](const MapFitTrial& t) { return LocalFit(t, false); }},
      {"RANSAC",
       [](const MapFitTrial& t) {
         const peers::PairRansacOptions options{.search_radius_m = t.radius_hint_m};
         return peers::PairRansacMapFit(t.map, t.problem.points, {}, options);
       }},
      {"RANSAC-NN",
       [](const MapFitTrial& t) {
         return peers::NearestRansacMapFit(t.map, t.problem.points, {});
       }},
      {"ICP", [](const MapFitTrial& t) { return peers::IcpMapFit(t.map, t.problem.points, {}); }}};
}

struct Score {
  int trials = 0;
  int successes = 0;
  int wrong_converged = 0;  // converged, but not within the success bounds
  std::vector<double> position_errors_m;
  std::vector<double> seconds;
};

// Runs `method` on `trial` and scores it at the vehicle: the correction's error moves the vehicle.
void RunMethod(const Method& method, const MapFitTrial& trial, Score* score) {
  const auto start = std::chrono::steady_clock::now();
  const mapmatch::MapFitResult fit = method.fit(trial);
  score->seconds.push_back(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  const geometry::Pose2& truth = trial.problem.truth;
  const double position_error = (fit.correction * trial.vehicle - truth * trial.vehicle).norm();
  const double rotation_error = mapmatch::ErrorOf(fit.correction, truth).rotation_rad;
  const bool success = fit.converged && position_error < 0.01 && rotation_error < 0.5 * kDeg;
  ++score->trials;
  score->position_errors_m.push_back(fit.converged ? position_error : INFINITY);
  if (success) ++score->successes;
  if (fit.converged && !success) ++score->wrong_converged;
}

double Median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

std::string SeedList(const std::vector<unsigned>& seeds) {
  std::string text;
  for (const unsigned s : seeds) text += (text.empty() ? "" : ",") + std::to_string(s);
  return text;
}

void PrintHeader(const std::vector<Method>& methods) {
  std::printf("%-8s", "outliers");
  for (const Method& m : methods) std::printf(" | %-27s", m.name.c_str());
  std::printf("\n%-8s", "");
  for (std::size_t k = 0; k < methods.size(); ++k)
    std::printf(" | %6s %6s %6s %6s", "succ", "wrong", "err mm", "us");
  std::printf("\n");
}

// Success and wrong-converged rates, the median position error at the vehicle in mm (non-converged
// fits count as infinite) and the median time per fit in µs.
void PrintRow(double outlier_percent, const std::vector<Score>& scores) {
  std::printf("%6.0f %%", outlier_percent);
  for (const Score& s : scores) {
    std::printf(" | %5.1f%% %5.1f%% %6.1f %6.0f", 100.0 * s.successes / s.trials,
                100.0 * s.wrong_converged / s.trials, 1e3 * Median(s.position_errors_m),
                1e6 * Median(s.seconds));
  }
  std::printf("\n");
  std::fflush(stdout);
}

// The same table's successes and wrong-converged fits as counts, so two methods whose rates
// round alike can be compared exactly.
void PrintCounts(const std::vector<double>& outlier_percents,
                 const std::vector<std::vector<Score>>& table) {
  std::printf("counts: successes / wrong of the trials per level\n");
  for (std::size_t level = 0; level < table.size(); ++level) {
    std::printf("%6.0f %%", outlier_percents[level]);
    for (const Score& s : table[level])
      std::printf(" | %6d %6d of %-11d", s.successes, s.wrong_converged, s.trials);
    std::printf("\n");
  }
}

// One table: every outlier level over `seeds`, `trials` problems per level and seed.
void RunTable(const MapFitBenchArgs& args, const std::vector<unsigned>& seeds,
              const std::string& title) {
  const std::vector<Method> methods = Methods();
  std::vector<MapFitTrials> streams;
  for (const unsigned seed : seeds) streams.emplace_back(seed);
  std::printf("-- %s: seeds %s, %d trials per outlier level and seed\n", title.c_str(),
              SeedList(seeds).c_str(), args.trials);
  PrintHeader(methods);
  std::vector<std::vector<Score>> table;
  for (const double percent : args.outlier_percents) {
    MapFitTrialOptions options = args.problems;
    options.outlier_fraction = percent / 100.0;
    std::vector<Score> scores(methods.size());
    for (MapFitTrials& stream : streams) {
      for (int t = 0; t < args.trials; ++t) {
        const MapFitTrial trial = stream.Next(options);
        for (std::size_t k = 0; k < methods.size(); ++k) RunMethod(methods[k], trial, &scores[k]);
      }
    }
    spdlog::info("{}: {} % outliers done", title, percent);
    PrintRow(percent, scores);
    table.push_back(std::move(scores));
  }
  PrintCounts(args.outlier_percents, table);
}

}  // namespace

Status RunMapFitBench(MapFitBenchArgs args) {
  cv::setNumThreads(1);
  if (args.problems.kind != "corridor" && args.problems.kind != "rooms")
    return InvalidInput("--kind: must be corridor or rooms, got '" + args.problems.kind + "'");
  if (args.problems.kind == "rooms" && args.problems.map_landmarks < 4)
    return InvalidInput("--map-landmarks: must be >= 4");
  if (args.outlier_percents.empty()) {
    args.outlier_percents = args.problems.kind == "rooms" ? std::vector<double>{70, 80, 90}
                                                          : std::vector<double>{50, 70, 80, 90};
  }
  std::printf(
      "== map fit, %s\n== success: error at the vehicle < 1 cm and < 0.5 deg; wrong: "
      "converged but not a success; err: median position error at the vehicle; us: "
      "median time per fit\n",
      DescribeTrials(args.problems).c_str());
  RunTable(args, args.seeds, "tuning seeds");
  if (!args.held_out_seeds.empty()) RunTable(args, args.held_out_seeds, "held-out seeds");
  return Status::Ok();
}

}  // namespace fleetloc::bench
