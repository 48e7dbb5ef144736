// Tests for poses.csv: exact round trip of every column and one error per broken rule.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "run_io/run.h"
#include "run_io/run_io_test_util.h"

namespace fleetloc::run_io {
namespace {

namespace fs = std::filesystem;
using testing::HasError;
using testing::TempDir;
using testing::WriteText;

constexpr char kHeader[] = "t,x,y,theta,sxx,sxy,sxt,syy,syt,stt,status,inliers\n";

class PosesCsvTest : public ::testing::Test {
 protected:
  Status ReadRows(const std::string& rows) {
    WriteText(path_, kHeader + rows);
    return ReadPosesCsv(path_).status();
  }
  TempDir dir_;
  fs::path path_ = dir_.path() / "poses.csv";
};

TEST_F(PosesCsvTest, RoundTripIsExact) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const std::vector<std::string> statuses = {"tracking", "coasting", "lost", "relocalized"};
  std::vector<PoseRecord> written;
  for (int i = 0; i < 40; ++i) {
    PoseRecord r;
    r.t = 1700000000.0 + i / 30.0;
    r.pose = {n(rng) * 100, n(rng) * 100, geometry::WrapAngle(n(rng) * 3)};
    const Eigen::Matrix3d a = Eigen::Matrix3d::NullaryExpr([&] { return n(rng) * 1e-3; });
    const Eigen::Matrix3d product = a * a.transpose();
    r.covariance = 0.5 * (product + product.transpose());  // exactly symmetric, as in the file
    r.status = statuses[i % 4];
    r.inliers = i * 3;
    written.push_back(r);
  }
  ASSERT_TRUE(WritePosesCsv(path_, written).ok());
  Result<std::vector<PoseRecord>> read = ReadPosesCsv(path_);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ((*read)[i].t, written[i].t);
    EXPECT_EQ((*read)[i].pose.ToVector(), written[i].pose.ToVector());
    EXPECT_EQ((*read)[i].covariance, written[i].covariance);
    EXPECT_EQ((*read)[i].status, written[i].status);
    EXPECT_EQ((*read)[i].inliers, written[i].inliers);
  }
}

TEST_F(PosesCsvTest, EmptyFileWithHeaderIsValid) {
  ASSERT_TRUE(WritePosesCsv(path_, {}).ok());
  EXPECT_EQ(testing::ReadText(path_), kHeader);
  Result<std::vector<PoseRecord>> read = ReadPosesCsv(path_);
  ASSERT_TRUE(read.ok());
  EXPECT_TRUE(read->empty());
}

TEST_F(PosesCsvTest, MissingFileIsNotFound) {
  EXPECT_TRUE(HasError(ReadPosesCsv(path_).status(), StatusCode::kNotFound, path_, 0, ""));
}

TEST_F(PosesCsvTest, BadRowsNameLineAndField) {
  const StatusCode bad = StatusCode::kInvalidInput;
  const std::string ok = "0,1,2,0.5,1,0,0,1,0,1,tracking,12\n";
  WriteText(path_, "t,x,y,theta,sxx,sxy,sxt,syy,syt,stt,state,inliers\n");
  EXPECT_TRUE(HasError(ReadPosesCsv(path_).status(), bad, path_, 1, "status"));
  EXPECT_TRUE(
      HasError(ReadRows(ok + "1,1,2,0.5,1,0,0,1,0,1,tracking\n"), bad, path_, 3, "inliers"));
  EXPECT_TRUE(HasError(ReadRows(ok + "1,1,2,0.5,1,0,0,1,0,1,tracking,3,4\n"), bad, path_, 3,
                       "(column 13)"));
  EXPECT_TRUE(
      HasError(ReadRows(ok + "1,1,2,0.5,1,0,0,1,0,1,drifting,3\n"), bad, path_, 3, "status"));
  EXPECT_TRUE(HasError(ReadRows(ok + "1,1,2,0.5,1,0,0,1,0,1,lost,-1\n"), bad, path_, 3, "inliers"));
  EXPECT_TRUE(
      HasError(ReadRows(ok + "1,1,2,0.5,1,0,0,1,0,1,lost,2.5\n"), bad, path_, 3, "inliers"));
  EXPECT_TRUE(HasError(ReadRows(ok + "1,1,2,0.5,1,nan,0,1,0,1,lost,2\n"), bad, path_, 3, "sxy"));
  EXPECT_TRUE(HasError(ReadRows(ok + "1,1,2,0.5,1,0,0,1,0,-1,lost,2\n"), bad, path_, 3, "stt"));
  EXPECT_TRUE(HasError(ReadRows(ok + "1,1,2,inf,1,0,0,1,0,1,lost,2\n"), bad, path_, 3, "theta"));
  EXPECT_TRUE(HasError(ReadRows(ok + "0,1,2,0.5,1,0,0,1,0,1,lost,2\n"), bad, path_, 3, "t"));
}

TEST_F(PosesCsvTest, WriterRefusesUnknownStatusAndNonFiniteValues) {
  PoseRecord r;
  r.status = "fine";
  EXPECT_TRUE(HasError(WritePosesCsv(path_, {r}), StatusCode::kInvalidInput, path_, 2, "status"));
  r.status = "lost";
  r.covariance(1, 2) = NAN;
  EXPECT_TRUE(HasError(WritePosesCsv(path_, {r, r}), StatusCode::kInvalidInput, path_, 2, "syt"));
  EXPECT_FALSE(fs::exists(path_));
}

}  // namespace
}  // namespace fleetloc::run_io
