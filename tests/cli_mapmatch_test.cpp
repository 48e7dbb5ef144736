// fleetctl mapmatch end to end (CONTRACT §6–7): a figure-3-like problem written as landmarks.csv
// and points.csv, the JSON correction checked against the truth; an unobservable rotation reported
// as converged false; and every bad input ending with exit status 2 and one line naming the file,
// line and field or the option.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "mapmatch/map_fit_problem.h"

namespace fleetloc::testing {
namespace {

constexpr double kDeg = M_PI / 180.0;
// A corridor of office corners (metres).
const std::vector<Eigen::Vector2d> kMap{{0, 0}, {4, 0}, {4, 3}, {0, 3}, {8, 0}, {8, 3}, {12, 0}};
const geometry::Pose2 kTruth{0.12, -0.08, 2.0 * kDeg};

class CliMapmatch : public ::testing::Test {
 protected:
  // Writes landmarks.csv (ids L0, L1, …) and points.csv with full precision.
  void WriteProblem(const std::vector<Eigen::Vector2d>& points) {
    std::ofstream landmarks(landmarks_);
    landmarks << std::setprecision(17) << "id,x,y\n";
    for (std::size_t i = 0; i < kMap.size(); ++i)
      landmarks << "L" << i << "," << kMap[i].x() << "," << kMap[i].y() << "\n";
    std::ofstream out(points_);
    out << std::setprecision(17) << "x,y\n";
    for (const Eigen::Vector2d& p : points) out << p.x() << "," << p.y() << "\n";
  }
  void WriteFigure3Problem(unsigned seed, const std::vector<int>& observed) {
    std::mt19937 rng(seed);
    WriteProblem(mapmatch::SimulateMapFitProblem(
                     kMap, observed, kTruth, {.noise_sigma_m = 0.02, .outlier_fraction = 0.7}, rng)
                     .points);
  }
  void WriteText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::trunc) << text;
  }
  CommandResult Mapmatch(const std::string& extra = "--radius 0.25") {
    return RunFleetctl("mapmatch --landmarks " + Quote(landmarks_) + " --points " + Quote(points_) +
                       " " + extra);
  }

  ScratchDir dir_{"cli_mapmatch"};
  std::string landmarks_ = dir_ / "landmarks.csv";
  std::string points_ = dir_ / "points.csv";
};

TEST_F(CliMapmatch, Figure3ProblemPrintsTheTrueCorrection) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    WriteFigure3Problem(seed, {0, 1, 2, 5});
    const CommandResult r = Mapmatch();
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json json = nlohmann::json::parse(r.out);
    for (const char* key : {"dx", "dy", "dtheta", "iterations", "inliers", "converged"})
      EXPECT_TRUE(json.contains(key)) << key;
    ASSERT_TRUE(json["converged"].get<bool>()) << r.out;
    // 30 points of σ = 2 cm per corner, ~2 outliers inside each 25 cm window: ~1 cm.
    EXPECT_NEAR(json["dx"].get<double>(), kTruth.x, 0.02) << "seed " << seed;
    EXPECT_NEAR(json["dy"].get<double>(), kTruth.y, 0.02) << "seed " << seed;
    EXPECT_NEAR(json["dtheta"].get<double>(), kTruth.theta, 0.3 * kDeg) << "seed " << seed;
    EXPECT_GE(json["inliers"].get<int>(), 110);  // 120 inliers, a few outliers
    EXPECT_LE(json["inliers"].get<int>(), 140);
    EXPECT_GT(json["iterations"].get<int>(), 1);
    EXPECT_GT(json["covariance"][2][2].get<double>(), 0.0);
  }
}

TEST_F(CliMapmatch, InitIsWhereTheFitStarts) {
  WriteFigure3Problem(9, {0, 1, 2, 5});
  const CommandResult from_zero = Mapmatch();
  const CommandResult from_truth = Mapmatch("--radius 0.25 --init 0.12,-0.08,0.0349");
  ASSERT_EQ(from_zero.exit_code, 0) << from_zero.err;
  ASSERT_EQ(from_truth.exit_code, 0) << from_truth.err;
  const nlohmann::json zero = nlohmann::json::parse(from_zero.out);
  const nlohmann::json truth = nlohmann::json::parse(from_truth.out);
  ASSERT_TRUE(truth["converged"].get<bool>()) << from_truth.out;
  EXPECT_LT(truth["iterations"].get<int>(), zero["iterations"].get<int>());
  EXPECT_NEAR(truth["dx"].get<double>(), zero["dx"].get<double>(), 1e-6) << "the same optimum";
}

TEST_F(CliMapmatch, ASingleClusterIsReportedAsNotConverged) {
  WriteFigure3Problem(4, {1});
  const CommandResult r = Mapmatch("--radius 0.25 --init 0.12,-0.08,0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_FALSE(json["converged"].get<bool>());
  EXPECT_NE(json["reason"].get<std::string>().find("rotation unobservable"), std::string::npos);
  EXPECT_EQ(json["dtheta"].get<double>(), 0.0) << "no guessed rotation";
}

TEST_F(CliMapmatch, BrokenFilesNameFileLineAndField) {
  WriteFigure3Problem(1, {0, 1, 2});
  const std::string landmarks_ok = ReadWhole(landmarks_);
  WriteText(points_, "x,y\n1,2\n3\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"points.csv:3"}));
  WriteText(points_, "x,y\n1,2\nnan,1\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"points.csv:3", "field 'x'"}));
  WriteText(points_, "1,2\n3,4\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"points.csv:1"}));
  WriteText(points_, "x,y\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"points.csv", "no points"}));
  WriteText(points_, "x,y\n1,2\n");
  WriteText(landmarks_, landmarks_ok + "L1,20,20\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"landmarks.csv:9", "field 'id'", "line 3"}));
  WriteText(landmarks_, landmarks_ok + "L7,4,3\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"landmarks.csv:9", "field 'x'", "line 4"}));
  WriteText(landmarks_, "id,x,y\nL0,1,inf\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"landmarks.csv:2", "field 'y'"}));
  WriteText(landmarks_, "id,x\nL0,1\n");
  EXPECT_TRUE(IsBadInput(Mapmatch(), {"landmarks.csv:1"}));
  EXPECT_TRUE(IsBadInput(RunFleetctl("mapmatch --landmarks " + Quote(dir_ / "none.csv") +
                                     " --points " + Quote(points_) + " --radius 1"),
                         {"none.csv"}));
}

TEST_F(CliMapmatch, BadOptionsNameTheOption) {
  WriteFigure3Problem(1, {0, 1, 2});
  for (const std::string radius : {"0", "-1", "nan", "abc", "1,2"}) {
    EXPECT_TRUE(IsBadInput(Mapmatch("--radius=" + radius), {"--radius"})) << radius;
  }
  for (const std::string init : {"1,2", "1,2,nan", "a,b,c", "1,2,3,4", "1,,2"}) {
    EXPECT_TRUE(IsBadInput(Mapmatch("--radius 0.3 --init=" + Quote(init)), {"--init"})) << init;
  }
}

}  // namespace
}  // namespace fleetloc::testing
